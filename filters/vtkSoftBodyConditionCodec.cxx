#include "vtkSoftBodyConditionCodec.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace
{

constexpr const char* kName = "ConditionName";
constexpr const char* kKind = "ConditionType";

void AddValues(vtkFieldData* field, const char* name, const std::vector<double>& values)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  field->AddArray(array);
}

void AddVector(vtkFieldData* field, const char* name, const softbody::Vec3& v)
{
  AddValues(field, name, { v.x(), v.y(), v.z() });
}

/// The values of a numeric field array, or false when it is missing.
bool Values(vtkFieldData* field, const char* name, std::vector<double>& values)
{
  vtkDataArray* array = field->GetArray(name);
  if (!array)
  {
    return false;
  }
  values.resize(static_cast<std::size_t>(array->GetNumberOfTuples() * array->GetNumberOfComponents()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    values[i] = array->GetComponent(static_cast<vtkIdType>(i) / array->GetNumberOfComponents(),
      static_cast<int>(static_cast<vtkIdType>(i) % array->GetNumberOfComponents()));
  }
  return true;
}

} // namespace

//------------------------------------------------------------------------------
void vtkSoftBodyConditionCodec::Encode(const softbody::Condition& c, vtkFieldData* field)
{
  vtkNew<vtkStringArray> name;
  name->SetName(kName);
  name->InsertNextValue(c.name);
  field->AddArray(name);
  AddValues(field, kKind, { static_cast<double>(c.kind) });
  AddValues(field, "HeldComponents",
    { c.heldAxes[0] ? 1.0 : 0.0, c.heldAxes[1] ? 1.0 : 0.0, c.heldAxes[2] ? 1.0 : 0.0 });
  AddVector(field, "Translation", c.translation);
  AddVector(field, "RotationAxis", c.rotationAxis);
  AddVector(field, "RotationCenter", c.rotationCenter);
  AddValues(field, "RotationAngle", { c.rotationAngle * 180.0 / std::numbers::pi });
  AddVector(field, "Force", c.force);
  AddValues(field, "ForceSpread", { static_cast<double>(c.spread) });
  AddValues(field, "Pressure", { c.pressure });
  AddVector(field, "PullTarget", c.pullTarget);
  AddValues(field, "PullStiffness", { c.pullStiffness });
  AddValues(field, "Profile", { static_cast<double>(c.profile.shape) });
  AddValues(field, "ProfileTime", { c.profile.duration });
  AddValues(field, "KeyframeTimes", c.profile.times);
  AddValues(field, "KeyframeFactors", c.profile.factors);
}

//------------------------------------------------------------------------------
void vtkSoftBodyConditionCodec::EncodeValuesOverTheRun(
  const std::vector<std::vector<softbody::Condition>>& overTheRun, vtkFieldData* field)
{
  // The values a property holds, as Encode writes them (degrees, SI units): the arrays of one
  // tuple of a fixed width. The kind, the held components, the spread and the profile's shape
  // never change during a run (a change of them builds the simulation anew). The XML marks the
  // same properties <RecordedWhilePlaying/> for the GUI's keyframe recorder (python.keyframes
  // checks the two lists agree).
  static const char* const kLive[] = { "Translation", "RotationAxis", "RotationCenter", "RotationAngle",
    "Force", "Pressure", "PullTarget", "PullStiffness", "ProfileTime" };
  if (overTheRun.empty())
  {
    return;
  }
  for (std::size_t c = 0; c < overTheRun.front().size(); ++c)
  {
    const std::string prefix = "ConditionValues " + overTheRun.front()[c].name + " ";
    for (const char* property : kLive)
    {
      vtkNew<vtkDoubleArray> values;
      values->SetName((prefix + property).c_str());
      for (const std::vector<softbody::Condition>& conditions : overTheRun)
      {
        vtkNew<vtkFieldData> one;
        Encode(conditions[c], one);
        std::vector<double> tuple;
        Values(one, property, tuple);
        values->SetNumberOfComponents(static_cast<int>(tuple.size()));
        values->InsertNextTuple(tuple.data());
      }
      field->AddArray(values);
    }
  }
}

//------------------------------------------------------------------------------
bool vtkSoftBodyConditionCodec::HasCondition(vtkFieldData* field)
{
  return field && field->GetAbstractArray(kName) && field->GetArray(kKind);
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyConditionCodec::Decode(vtkFieldData* field, softbody::Condition& c)
{
  if (!HasCondition(field))
  {
    return "it is not the output of a Soft Body Condition (its field data has no ConditionName "
           "and ConditionType). Connect Soft Body Condition filters to the Conditions input.";
  }
  vtkStringArray* name = vtkStringArray::SafeDownCast(field->GetAbstractArray(kName));
  c = softbody::Condition{};
  c.name = name && name->GetNumberOfValues() > 0 ? name->GetValue(0) : std::string("Condition");
  std::vector<double> v;
  const auto read = [&](const char* array, std::size_t count) {
    if (!Values(field, array, v) || (count > 0 && v.size() != count))
    {
      throw std::string(array);
    }
    return v;
  };
  try
  {
    const int kind = static_cast<int>(read(kKind, 1)[0]);
    if (kind < 0 || kind > static_cast<int>(softbody::ConditionKind::Pull))
    {
      return "its ConditionType " + std::to_string(kind) + " is not one of 0 .. 4.";
    }
    c.kind = static_cast<softbody::ConditionKind>(kind);
    const std::vector<double> held = read("HeldComponents", 3);
    c.heldAxes = { held[0] != 0.0, held[1] != 0.0, held[2] != 0.0 };
    const auto vec = [&](const char* array) {
      const std::vector<double> x = read(array, 3);
      return softbody::Vec3(x[0], x[1], x[2]);
    };
    c.translation = vec("Translation");
    c.rotationAxis = vec("RotationAxis");
    c.rotationCenter = vec("RotationCenter");
    c.rotationAngle = read("RotationAngle", 1)[0] * std::numbers::pi / 180.0;
    c.force = vec("Force");
    const int spread = static_cast<int>(read("ForceSpread", 1)[0]);
    if (spread < 0 || spread > static_cast<int>(softbody::ForceSpread::PerPoint))
    {
      return "its ForceSpread " + std::to_string(spread) + " is not one of 0 (by mass), 1 (by area), 2 (per point).";
    }
    c.spread = static_cast<softbody::ForceSpread>(spread);
    c.pressure = read("Pressure", 1)[0];
    c.pullTarget = vec("PullTarget");
    c.pullStiffness = read("PullStiffness", 1)[0];
    const int profile = static_cast<int>(read("Profile", 1)[0]);
    if (profile < 0 || profile > static_cast<int>(softbody::TimeProfileShape::Keyframes))
    {
      return "its Profile " + std::to_string(profile) + " is not one of 0 (constant), 1 (ramp), 2 (sinusoid), 3 (keyframes).";
    }
    c.profile.shape = static_cast<softbody::TimeProfileShape>(profile);
    c.profile.duration = read("ProfileTime", 1)[0];
    c.profile.times = read("KeyframeTimes", 0);
    c.profile.factors = read("KeyframeFactors", 0);
  }
  catch (const std::string& missing)
  {
    return "its field data array " + missing + " is missing or has the wrong size.";
  }
  return {};
}

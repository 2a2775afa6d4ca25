#include "vtkSoftBodyCondition.h"

#include "vtkSoftBodyConditionCodec.h"

#include "softbody/common/errors.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTransform.h"

#include <cmath>
#include <numbers>
#include <sstream>

vtkStandardNewMacro(vtkSoftBodyCondition);

namespace
{

/// The names of the arrays `data` has, for a message ("none" when it has none).
std::string ArrayNames(vtkDataSet* data)
{
  std::ostringstream names;
  int listed = 0;
  for (vtkFieldData* arrays : { static_cast<vtkFieldData*>(data->GetPointData()),
         static_cast<vtkFieldData*>(data->GetCellData()) })
  {
    for (int i = 0; i < arrays->GetNumberOfArrays(); ++i)
    {
      if (const char* name = arrays->GetArrayName(i))
      {
        names << (listed++ ? ", " : "") << "'" << name << "'";
      }
    }
  }
  return listed ? names.str() : std::string("none");
}

bool NonZero(vtkDataArray* array, vtkIdType tuple)
{
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    if (array->GetComponent(tuple, c) != 0.0)
    {
      return true;
    }
  }
  return false;
}

} // namespace

//------------------------------------------------------------------------------
vtkSoftBodyCondition::vtkSoftBodyCondition()
{
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Pinned");
}

//------------------------------------------------------------------------------
void vtkSoftBodyCondition::AddKeyframe(double time, double factor)
{
  this->KeyframeTimes.push_back(time);
  this->KeyframeFactors.push_back(factor);
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkSoftBodyCondition::RemoveAllKeyframes()
{
  if (!this->KeyframeTimes.empty())
  {
    this->KeyframeTimes.clear();
    this->KeyframeFactors.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkSoftBodyCondition::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyCondition::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // A condition is made on the body at rest, as the Soft Body filter reads its input: the time
  // is not forwarded, so the body's source is asked the same by both and never re-executes
  // between them (which would rebuild the simulation).
  if (vtkInformation* inInfo = inputVector[0]->GetInformationObject(0))
  {
    inInfo->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyCondition::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  const std::string who = "Condition '" + this->ConditionName + "'";
  const vtkIdType n = input->GetNumberOfPoints();

  // The set, in the input's point numbers.
  std::vector<char> inSet(static_cast<std::size_t>(n), 0);
  std::string regionName;
  switch (this->Region)
  {
    case REGION_ARRAY:
    {
      int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
      vtkDataArray* array = this->GetInputArrayToProcess(0, input, association);
      if (!array)
      {
        vtkInformation* which = this->GetInputArrayInformation(0);
        const char* name = which->Get(vtkDataObject::FIELD_NAME());
        vtkErrorMacro(<< who << ": the input has no numeric array '" << (name ? name : "")
                      << "' to select points with. Its arrays: " << ArrayNames(input) << ".");
        return 0;
      }
      regionName = std::string("array '") + (array->GetName() ? array->GetName() : "") + "'";
      if (association == vtkDataObject::FIELD_ASSOCIATION_CELLS)
      {
        vtkNew<vtkIdList> cellPoints;
        for (vtkIdType cell = 0; cell < input->GetNumberOfCells(); ++cell)
        {
          if (NonZero(array, cell))
          {
            input->GetCellPoints(cell, cellPoints);
            for (vtkIdType k = 0; k < cellPoints->GetNumberOfIds(); ++k)
            {
              inSet[static_cast<std::size_t>(cellPoints->GetId(k))] = 1;
            }
          }
        }
      }
      else
      {
        for (vtkIdType i = 0; i < n; ++i)
        {
          inSet[static_cast<std::size_t>(i)] = NonZero(array, i) ? 1 : 0;
        }
      }
      break;
    }
    case REGION_BOX:
    {
      if (!(this->BoxScale[0] > 0 && this->BoxScale[1] > 0 && this->BoxScale[2] > 0))
      {
        vtkErrorMacro(<< who << ": the box's scale (" << this->BoxScale[0] << ", "
                      << this->BoxScale[1] << ", " << this->BoxScale[2]
                      << ") must be positive along each axis.");
        return 0;
      }
      // The unit cube scaled, rotated (z, x, y) and moved, as ParaView's box widget draws it.
      vtkNew<vtkTransform> box;
      box->Translate(this->BoxPosition);
      box->RotateZ(this->BoxRotation[2]);
      box->RotateX(this->BoxRotation[0]);
      box->RotateY(this->BoxRotation[1]);
      box->Scale(this->BoxScale);
      box->Inverse();
      const double slack = 1e-12;
      for (vtkIdType i = 0; i < n; ++i)
      {
        double q[3];
        box->TransformPoint(input->GetPoint(i), q);
        inSet[static_cast<std::size_t>(i)] = q[0] >= -slack && q[0] <= 1 + slack && q[1] >= -slack &&
            q[1] <= 1 + slack && q[2] >= -slack && q[2] <= 1 + slack;
      }
      regionName = "box";
      break;
    }
    case REGION_SPHERE:
    {
      if (!(this->SphereRadius > 0))
      {
        vtkErrorMacro(<< who << ": the sphere's radius " << this->SphereRadius << " m must be positive.");
        return 0;
      }
      for (vtkIdType i = 0; i < n; ++i)
      {
        const double* p = input->GetPoint(i);
        const double d2 = std::pow(p[0] - this->SphereCenter[0], 2) +
          std::pow(p[1] - this->SphereCenter[1], 2) + std::pow(p[2] - this->SphereCenter[2], 2);
        inSet[static_cast<std::size_t>(i)] = d2 <= this->SphereRadius * this->SphereRadius;
      }
      regionName = "sphere";
      break;
    }
    case REGION_HALF_SPACE:
    {
      const double* nrm = this->PlaneNormal;
      const double length = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      if (!(length > 0))
      {
        vtkErrorMacro(<< who << ": the plane's normal (" << nrm[0] << ", " << nrm[1] << ", "
                      << nrm[2] << ") has no direction.");
        return 0;
      }
      // Within a trillionth of the body's size of the plane counts as on it (a face exactly
      // on the plane is selected whole, whatever the rounding of its coordinates).
      const double slack = 1e-12 * std::max(input->GetLength(), 1e-300);
      for (vtkIdType i = 0; i < n; ++i)
      {
        const double* p = input->GetPoint(i);
        const double side = ((p[0] - this->PlaneOrigin[0]) * nrm[0] +
                              (p[1] - this->PlaneOrigin[1]) * nrm[1] + (p[2] - this->PlaneOrigin[2]) * nrm[2]) /
          length;
        inSet[static_cast<std::size_t>(i)] = side >= -slack;
      }
      regionName = "half-space";
      break;
    }
    case REGION_ALL:
      std::fill(inSet.begin(), inSet.end(), 1);
      regionName = "all points";
      break;
    default:
      vtkErrorMacro(<< who << ": Region " << this->Region
                    << " is not one of 0 (array), 1 (box), 2 (sphere), 3 (half-space), 4 (all points).");
      return 0;
  }

  softbody::Condition condition;
  condition.name = this->ConditionName;
  if (this->ConditionType < FIXED || this->ConditionType > PULL)
  {
    vtkErrorMacro(<< who << ": ConditionType " << this->ConditionType
                  << " is not one of 0 (Fixed), 1 (Prescribed Motion), 2 (Force), 3 (Pressure), 4 (Pull).");
    return 0;
  }
  if (this->ForceSpread < BY_MASS || this->ForceSpread > PER_POINT)
  {
    vtkErrorMacro(<< who << ": ForceSpread " << this->ForceSpread
                  << " is not one of 0 (by mass), 1 (by area), 2 (per point).");
    return 0;
  }
  if (this->Profile < CONSTANT || this->Profile > KEYFRAMES)
  {
    vtkErrorMacro(<< who << ": Profile " << this->Profile
                  << " is not one of 0 (constant), 1 (ramp), 2 (sinusoid), 3 (keyframes).");
    return 0;
  }
  condition.kind = static_cast<softbody::ConditionKind>(this->ConditionType);
  condition.heldAxes = { this->HeldComponents[0] != 0, this->HeldComponents[1] != 0,
    this->HeldComponents[2] != 0 };
  condition.translation = softbody::Vec3(this->Translation[0], this->Translation[1], this->Translation[2]);
  condition.rotationAxis = softbody::Vec3(this->RotationAxis[0], this->RotationAxis[1], this->RotationAxis[2]);
  condition.rotationCenter =
    softbody::Vec3(this->RotationCenter[0], this->RotationCenter[1], this->RotationCenter[2]);
  condition.rotationAngle = this->RotationAngle * std::numbers::pi / 180.0;
  condition.force = softbody::Vec3(this->Force[0], this->Force[1], this->Force[2]);
  condition.spread = static_cast<softbody::ForceSpread>(this->ForceSpread);
  condition.pressure = this->Pressure;
  condition.pullTarget = softbody::Vec3(this->PullTarget[0], this->PullTarget[1], this->PullTarget[2]);
  condition.pullStiffness = this->PullStiffness;
  condition.profile.shape = static_cast<softbody::TimeProfileShape>(this->Profile);
  condition.profile.duration = this->ProfileTime;
  condition.profile.times = this->KeyframeTimes;
  condition.profile.factors = this->KeyframeFactors;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("InputPointId");
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (inSet[static_cast<std::size_t>(i)])
    {
      points->InsertNextPoint(input->GetPoint(i));
      ids->InsertNextValue(i);
      condition.points.push_back(static_cast<std::int32_t>(condition.points.size()));
    }
  }
  // Refused here with the values given, so the panel that set them shows the message (the
  // Soft Body filter checks again against its body).
  try
  {
    std::vector<std::string> warnings;
    softbody::validateConditions({ condition }, condition.points.size(), warnings);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  if (condition.points.empty())
  {
    vtkWarningMacro(<< who << ": its " << regionName << " selects none of the input's " << n
                    << " points, so it does nothing. Move or resize the region.");
  }
  condition.points.clear();

  vtkNew<vtkCellArray> vertices;
  for (vtkIdType k = 0; k < points->GetNumberOfPoints(); ++k)
  {
    vertices->InsertNextCell(1, &k);
  }
  output->SetPoints(points);
  output->SetVerts(vertices);
  output->GetPointData()->AddArray(ids);
  vtkSoftBodyConditionCodec::Encode(condition, output->GetFieldData());
  return 1;
}

//------------------------------------------------------------------------------
void vtkSoftBodyCondition::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ConditionName: " << this->ConditionName << "\n";
  os << indent << "ConditionType: " << this->ConditionType << "\n";
  os << indent << "Region: " << this->Region << "\n";
  os << indent << "Keyframes: " << this->KeyframeTimes.size() << "\n";
}

#include "vtkSoftBodyConditionInput.h"

#include "vtkSoftBodyArrays.h"
#include "vtkSoftBodyConditionCodec.h"
#include "vtkSoftBodyDistribution.h"

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointSet.h"
#include "vtkStaticPointLocator.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <sstream>

namespace
{

/// The coordinates of `set`'s points, gathered from every rank under MPI.
std::vector<double> SetCoordinates(vtkPointSet* set)
{
  std::vector<double> local(static_cast<std::size_t>(3 * set->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < set->GetNumberOfPoints(); ++i)
  {
    set->GetPoint(i, local.data() + 3 * i);
  }
  vtkMultiProcessController* controller = vtkSoftBodyDistribution::ParallelController();
  if (!controller)
  {
    return local;
  }
  const int ranks = controller->GetNumberOfProcesses();
  const long long mine = static_cast<long long>(local.size());
  std::vector<long long> lengths(static_cast<std::size_t>(ranks));
  controller->AllGather(&mine, lengths.data(), 1);
  std::vector<vtkIdType> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    counts[static_cast<std::size_t>(r)] = static_cast<vtkIdType>(lengths[static_cast<std::size_t>(r)]);
    offsets[static_cast<std::size_t>(r)] = total;
    total += counts[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(total));
  controller->AllGatherV(local.data(), all.data(), static_cast<vtkIdType>(local.size()),
    counts.data(), offsets.data());
  return all;
}

} // namespace

//------------------------------------------------------------------------------
std::string vtkSoftBodyConditionInput::Read(vtkInformationVector* port,
  vtkUnstructuredGrid* body, std::vector<softbody::Condition>& conditions)
{
  const int count = port ? port->GetNumberOfInformationObjects() : 0;
  Key key{ { body, vtkSoftBodyArrays::ContentMTime(body) } };
  std::vector<vtkDataObject*> objects;
  for (int k = 0; k < count; ++k)
  {
    vtkDataObject* object = port->GetInformationObject(k)->Get(vtkDataObject::DATA_OBJECT());
    objects.push_back(object);
    key.emplace_back(object, vtkSoftBodyArrays::ContentMTime(vtkDataSet::SafeDownCast(object)));
  }
  if (key == this->Converted)
  {
    conditions = this->Conditions;
    this->Warnings.clear(); // said when converted
    return {};
  }
  conditions.clear();
  this->Warnings.clear();
  if (count == 0 || body->GetNumberOfPoints() == 0) // an empty body is refused by the filter
  {
    this->Converted = key;
    this->Conditions.clear();
    return {};
  }
  const bool distributed = vtkSoftBodyDistribution::ParallelController() != nullptr;
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(body);
  locator->BuildLocator();
  const double tolerance = 1e-9 * std::max(body->GetLength(), 1e-300);
  vtkNew<vtkIdList> found;
  std::vector<char> taken(static_cast<std::size_t>(body->GetNumberOfPoints()), 0);
  for (int k = 0; k < count; ++k)
  {
    vtkPointSet* set = vtkPointSet::SafeDownCast(objects[static_cast<std::size_t>(k)]);
    softbody::Condition condition;
    const std::string error = set ? vtkSoftBodyConditionCodec::Decode(set->GetFieldData(), condition)
                                  : std::string("it is not a point set.");
    if (!error.empty())
    {
      return "Conditions input " + std::to_string(k) + ": " + error;
    }
    const std::vector<double> xyz = SetCoordinates(set);
    std::size_t elsewhere = 0; // set points of another rank's bodies
    for (std::size_t p = 0; p < xyz.size(); p += 3)
    {
      locator->FindPointsWithinRadius(tolerance, xyz.data() + p, found);
      elsewhere += found->GetNumberOfIds() == 0 ? 1 : 0;
      if (found->GetNumberOfIds() == 0 && !distributed)
      {
        std::ostringstream s;
        s << "Condition '" << condition.name << "': its point (" << xyz[p] << ", " << xyz[p + 1]
          << ", " << xyz[p + 2] << ") is not a point of the body. Make the condition from the "
          << "body's mesh (the Soft Body filter's input, or a filter that keeps its points).";
        return s.str();
      }
      for (vtkIdType j = 0; j < found->GetNumberOfIds(); ++j)
      {
        const vtkIdType id = found->GetId(j);
        if (!taken[static_cast<std::size_t>(id)])
        {
          taken[static_cast<std::size_t>(id)] = 1;
          condition.points.push_back(static_cast<std::int32_t>(id));
        }
      }
    }
    for (std::int32_t id : condition.points)
    {
      taken[static_cast<std::size_t>(id)] = 0;
    }
    std::sort(condition.points.begin(), condition.points.end());
    const bool total = condition.kind == softbody::ConditionKind::Pull ||
      (condition.kind == softbody::ConditionKind::Force && condition.spread != softbody::ForceSpread::PerPoint);
    if (total && elsewhere > 0 && !condition.points.empty())
    {
      this->Warnings.push_back("Condition '" + condition.name + "' spans bodies on several ranks: each "
        "rank spreads its whole force over its own part of the set. Spread it per point, or keep the "
        "bodies together (Collisions = Obstacles + Bodies simulates every body on rank 0).");
    }
    conditions.push_back(std::move(condition));
  }
  this->Converted = key;
  this->Conditions = conditions;
  return {};
}

#include "vtkSoftBodyFloorPlacement.h"

#include "vtkSoftBodyParameters.h"

#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"

#include "softbody/common/validation.h"

#include <cmath>
#include <limits>

//------------------------------------------------------------------------------
std::string vtkSoftBodyFloorPlacement::Place(int placement, vtkPointSet* localBodies,
  vtkMultiProcessController* controller, softbody::Scene& scene)
{
  if (!scene.floorActive() || placement == vtkSoftBodyParameters::FLOOR_THROUGH_FLOOR_ORIGIN)
  {
    return {};
  }
  const double length = scene.floor.normal.norm();
  if (!(length > 0.0) || !std::isfinite(length))
  {
    return {}; // validateScene refuses the normal, quoting it
  }
  const softbody::Vec3 normal = scene.floor.normal / length;
  // The lowest point's height above the plane through FloorOrigin (negative: below it).
  double lowest = std::numeric_limits<double>::infinity();
  double farthest = scene.floor.origin.cwiseAbs().maxCoeff(); // the coordinates' scale
  vtkPoints* points = localBodies ? localBodies->GetPoints() : nullptr;
  for (vtkIdType i = 0; points && i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    const softbody::Vec3 p(x[0], x[1], x[2]);
    // NaN coordinates compare false and are skipped here; the input check refuses them.
    lowest = std::min(lowest, normal.dot(p - scene.floor.origin));
    farthest = std::max(farthest, p.cwiseAbs().maxCoeff());
  }
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    double everywhere[2] = { lowest, farthest };
    controller->AllReduce(&lowest, &everywhere[0], 1, vtkCommunicator::MIN_OP);
    controller->AllReduce(&farthest, &everywhere[1], 1, vtkCommunicator::MAX_OP);
    lowest = everywhere[0];
    farthest = everywhere[1];
  }
  if (!std::isfinite(lowest) || (placement == vtkSoftBodyParameters::FLOOR_AUTOMATIC && lowest >= 0.0))
  {
    return {}; // no points, or a body that starts on or above the floor: FloorOrigin stands
  }
  const softbody::Vec3 given = scene.floor.origin;
  // A few units in the last place below the lowest point, so that rounding the plane's origin
  // leaves no point under it (far from the origin, on a tilted floor, it would by 1e-11 m).
  const double rounding = 16.0 * std::numeric_limits<double>::epsilon() * farthest;
  scene.floor.origin = given + (lowest - rounding) * normal;
  if (placement != vtkSoftBodyParameters::FLOOR_AUTOMATIC)
  {
    return {}; // asked for: field data FloorOrigin says where it went
  }
  return "The body starts up to " + softbody::check::quote(-lowest) +
    " m below the floor through FloorOrigin " + softbody::check::quote(given) +
    " (normal " + softbody::check::quote(normal) + "): the floor is placed under the body instead, through " +
    softbody::check::quote(scene.floor.origin) +
    " (FloorPlacement Automatic). Set FloorPlacement to Through Floor Origin to lift the body onto "
    "that floor at t = 0.";
}

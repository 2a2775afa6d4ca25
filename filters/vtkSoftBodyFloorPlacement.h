/**
 * @class   vtkSoftBodyFloorPlacement
 * @brief   Where the Soft Body filter's floor goes: through FloorOrigin, or under the body.
 *
 * A mesh in scanner or CAD coordinates can lie anywhere, often below the plane through the
 * default FloorOrigin (0 0 0): lifting it onto that floor moves the whole body away from where
 * the user's data put it. FloorPlacement Automatic keeps FloorOrigin for a body that starts
 * above it (a drop, as the user set it up) and otherwise puts the floor under the body, through
 * its lowest point along the normal, and says so; Under the Body always does that; Through
 * Floor Origin never does.
 *
 * Under MPI every rank holds some of the bodies (or none): the lowest point is reduced over all
 * ranks, so every rank gets the floor the serial run gets. Collective: every rank must call it.
 */
#ifndef vtkSoftBodyFloorPlacement_h
#define vtkSoftBodyFloorPlacement_h

#include "softbody/scene/scene.h"

#include <string>

class vtkMultiProcessController;
class vtkPointSet;

class vtkSoftBodyFloorPlacement
{
public:
  /// Moves `scene.floor.origin` as `placement` (vtkSoftBodyParameters::FloorPlacementType)
  /// asks, from the points of `localBodies` (this rank's; null: none) and, with a `controller`
  /// of several processes, every rank's. Does nothing where the floor is not active. Returns
  /// the warning to give when Automatic moved the floor off FloorOrigin, quoting both; else
  /// empty.
  static std::string Place(int placement, vtkPointSet* localBodies,
    vtkMultiProcessController* controller, softbody::Scene& scene);
};

#endif

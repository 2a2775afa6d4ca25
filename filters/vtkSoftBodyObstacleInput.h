/**
 * @class   vtkSoftBodyObstacleInput
 * @brief   The Soft Body filter's Obstacles input (port 2) as core obstacle surfaces.
 *
 * Each connection may be any vtkDataSet: its outer surface (vtkDataSetSurfaceFilter) is
 * triangulated (vtkTriangleFilter; vertices and lines dropped) and kept in its orientation.
 * Obstacles are one-sided: the free side is the one the triangles' normals (b - a) x (c - a)
 * point to, so a closed surface with outward normals (vtkSphereSource, a closed STL) pushes
 * bodies out, and an open one (a plane, a ramp) pushes them to its normal side. Flip an
 * obstacle with Reverse Sense (vtkReverseSense) when it pushes the wrong way.
 *
 * Moving obstacles: a connection whose producer advertises times is requested at each frame
 * time the simulation passes (the filter's time protocol); its velocity over a frame is the
 * change of its vertices from the previous frame over the frame interval when both frames have
 * the same points, zero otherwise (topology changes: the obstacle jumps, it is not swept).
 */
#ifndef vtkSoftBodyObstacleInput_h
#define vtkSoftBodyObstacleInput_h

#include "softbody/collision/obstacle.h"

#include "vtkType.h"

#include <string>
#include <vector>

class vtkDataObject;
class vtkInformation;

namespace vtkSoftBodyObstacleInput
{
/// Empty when `object` is a vtkDataSet (or absent); otherwise a message naming its type.
std::string TypeError(vtkDataObject* object);

/// The triangulated outer surface of `object` (a vtkDataSet) in its own orientation.
softbody::ObstacleSurface ToObstacle(vtkDataObject* object);

/// Whether a connection's producer advertises time steps or a time range (a moving obstacle).
bool IsTemporal(vtkInformation* inputInfo);

/// `end` with per-vertex velocities (end - start) / interval when both have the same vertex
/// count and triangles; `end` unchanged (static over the frame) otherwise.
softbody::ObstacleSurface WithVelocities(
  softbody::ObstacleSurface end, const softbody::ObstacleSurface& start, double interval);
}

#endif

// The body's conditions as the GPU step reads them: the loads per point, which components of
// which points are held, and where the held points must be. The values come from core's
// BoundaryConditions on the host (the same code the CPU stepper calls, so they are its values
// to the bit) and are uploaded only when they change: once for Fixed points and constant
// forces, every step for a Prescribed motion or a force with a time profile. Runs on the GL
// thread.
#pragma once

#include "storage_buffer.h"

#include "softbody/common/geometry.h"
#include "softbody/scene/boundary_conditions.h"

#include <cstdint>
#include <vector>

namespace softbody::gpu
{

class ConditionBuffers
{
public:
  /// `conditions` and `rest` must outlive this object; new values given to `conditions`
  /// (replaceValues) are read after valuesChanged().
  ConditionBuffers(const BoundaryConditions& conditions, const std::vector<Vec3>& rest);

  bool hasLoads() const { return HasLoads; }
  bool hasHeldPoints() const { return !HeldList.empty(); }
  std::size_t heldPointCount() const { return HeldList.size(); }

  /// The loads at time t into loads() (core: BoundaryConditions::addLoads).
  void updateLoads(double t);
  /// The held points' positions and velocities at time t into heldTargets() (core:
  /// BoundaryConditions::holdPoints).
  void updateHeldTargets(double t);
  /// The conditions got new values: the next updates upload whatever they compute.
  void valuesChanged();

  const StorageBuffer& loads() const { return Loads; }             ///< dvec4 per point [N]
  const StorageBuffer& heldAxes() const { return HeldAxes; }       ///< uint per point, bit k: k held
  const StorageBuffer& heldPoints() const { return HeldPoints; }   ///< int per held point
  const StorageBuffer& heldTargets() const { return HeldTargets; } ///< x, v (dvec4) per held point

private:
  const BoundaryConditions& Conditions;
  const std::vector<Vec3>& Rest;
  bool HasLoads = false;
  bool MovesPoints = false;
  bool LoadsVary = false; ///< some load has a time profile: recomputed at every evaluation
  std::vector<std::int32_t> HeldList;
  StorageBuffer Loads, HeldAxes, HeldPoints, HeldTargets;
  // Host scratch, kept between steps so that an unchanged value is not uploaded again.
  std::vector<Vec3> LoadsHost, HeldX, HeldV;
  std::vector<double> Packed; ///< the values as the buffer holds them (dvec4 per entry)
  std::vector<double> UploadedLoads, UploadedTargets;
  bool LoadsCurrent = false, TargetsCurrent = false;
};

} // namespace softbody::gpu

#include "condition_buffers.h"

namespace softbody::gpu
{
namespace
{

/// Uploads `packed` unless it equals what `uploaded` says the buffer already holds.
void uploadIfChanged(StorageBuffer& buffer, const std::vector<double>& packed, std::vector<double>& uploaded)
{
  if (packed != uploaded)
  {
    buffer.upload(packed.data(), packed.size() * sizeof(double));
    uploaded = packed;
  }
}

/// Whether a load's value changes with time (a profile that is not constant).
bool loadsVary(const BoundaryConditions& conditions)
{
  for (const Condition& c : conditions.conditions())
  {
    if (!c.holds() && c.profile.shape != TimeProfileShape::Constant)
    {
      return true;
    }
  }
  return false;
}

} // namespace

ConditionBuffers::ConditionBuffers(const BoundaryConditions& conditions, const std::vector<Vec3>& rest)
  : Conditions(conditions)
  , Rest(rest)
  , HasLoads(conditions.hasLoads())
  , MovesPoints(conditions.movesPoints())
  , LoadsVary(loadsVary(conditions))
{
  const std::vector<AxisMask>& held = conditions.heldAxes(); // empty when nothing is held
  std::vector<std::uint32_t> axes(held.begin(), held.end());
  for (std::size_t i = 0; i < held.size(); ++i)
  {
    if (held[i] != 0)
    {
      HeldList.push_back(static_cast<std::int32_t>(i));
    }
  }
  HeldAxes = StorageBuffer::fromVector("held axes", axes);
  HeldPoints = StorageBuffer::fromVector("held points", HeldList);
  HeldTargets = StorageBuffer("held targets", 8 * sizeof(double) * HeldList.size());
  Loads = StorageBuffer("loads", HasLoads ? 4 * sizeof(double) * rest.size() : 0);
  if (!HeldList.empty())
  {
    HeldX.assign(rest.size(), Vec3::Zero());
    HeldV.assign(rest.size(), Vec3::Zero());
  }
}

void ConditionBuffers::updateLoads(double t)
{
  if (!HasLoads || (LoadsCurrent && !LoadsVary))
  {
    return;
  }
  // Pressure and Pull, the loads that depend on the positions, are left to the CPU
  // (tryCreateGpuMassSpring), so the rest positions serve as the state here.
  LoadsHost.assign(Rest.size(), Vec3::Zero());
  Conditions.addLoads(t, Rest, LoadsHost);
  Packed.assign(4 * LoadsHost.size(), 0.0);
  for (std::size_t i = 0; i < LoadsHost.size(); ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      Packed[4 * i + static_cast<std::size_t>(d)] = LoadsHost[i](d);
    }
  }
  uploadIfChanged(Loads, Packed, UploadedLoads);
  LoadsCurrent = true;
}

void ConditionBuffers::updateHeldTargets(double t)
{
  if (HeldList.empty() || (TargetsCurrent && !MovesPoints))
  {
    return;
  }
  Conditions.holdPoints(t, HeldX, HeldV); // writes the held components of the held points only
  Packed.assign(8 * HeldList.size(), 0.0);
  for (std::size_t k = 0; k < HeldList.size(); ++k)
  {
    const auto i = static_cast<std::size_t>(HeldList[k]);
    for (int d = 0; d < 3; ++d)
    {
      Packed[8 * k + static_cast<std::size_t>(d)] = HeldX[i](d);
      Packed[8 * k + 4 + static_cast<std::size_t>(d)] = HeldV[i](d);
    }
  }
  uploadIfChanged(HeldTargets, Packed, UploadedTargets);
  TargetsCurrent = true;
}

void ConditionBuffers::valuesChanged()
{
  LoadsVary = loadsVary(Conditions);
  LoadsCurrent = false;
  TargetsCurrent = false;
}

} // namespace softbody::gpu

// Current over rest volume of tets: the "VolumeRatio" every stepper reports per input tet.
#pragma once

#include "softbody/common/geometry.h"

#include <cstdint>
#include <vector>

namespace softbody
{

/// ratio[k] = V(positions, tets[s]) / restVolume[s] with s = storageSlot[k], or s = k when
/// storageSlot is empty (steppers that keep tets in input order).
std::vector<double> tetVolumeRatios(const std::vector<Tet>& tets, const std::vector<double>& restVolume,
  const std::vector<Vec3>& positions, const std::vector<std::int32_t>& storageSlot = {});

} // namespace softbody

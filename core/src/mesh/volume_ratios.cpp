#include "softbody/mesh/volume_ratios.h"

namespace softbody
{

std::vector<double> tetVolumeRatios(const std::vector<Tet>& tets, const std::vector<double>& restVolume,
  const std::vector<Vec3>& positions, const std::vector<std::int32_t>& storageSlot)
{
  const std::vector<Vec3>& x = positions;
  std::vector<double> ratios(tets.size());
  for (std::size_t k = 0; k < tets.size(); ++k)
  {
    const std::size_t s = storageSlot.empty() ? k : static_cast<std::size_t>(storageSlot[k]);
    const Tet& t = tets[s];
    ratios[k] = signedTetVolume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) / restVolume[s];
  }
  return ratios;
}

} // namespace softbody

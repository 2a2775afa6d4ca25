// The colored Gauss-Seidel solver's kernels, four constraints at a time.
//
// Within one graph color no two constraints share a movable particle, so a color's
// constraints can be projected in any grouping: these project [begin, end) of a batch stored
// color by color (pbd_color_storage.cpp) in blocks of four lanes (common/simd.h), the last
// partial block one lane at a time. Every lane runs the same template as the scalar kernel
// (pbd_kernels.h, namespace lanes) and the corrections are added in constraint order, so the
// result is the same bit for bit as projecting the range one constraint at a time, at every
// SimdLevel (tests/unit/test_wide_kernels.cpp).
//
// Per-constraint data is read where the batch keeps it: rest lengths, rest volumes and
// multipliers are contiguous per batch (one load per four lanes), the two per-step constants
// interleaved in ProjectionParameters (a strided load), the particles' positions and inverse
// masses gathered through the constraint's indices.
#pragma once

#include "softbody/common/simd.h"
#include "softbody/pbd/pbd_constraints.h"

#include <vector>

namespace softbody
{

/// Projects links [begin, end) of one color: x and the links' multipliers updated.
void projectLinksWide(DistanceBatch& batch, std::size_t begin, std::size_t end, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level = bestSimdLevel());

/// Projects tet volumes [begin, end) of one color: x and the tets' multipliers updated.
void projectVolumesWide(VolumeBatch& batch, std::size_t begin, std::size_t end, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level = bestSimdLevel());

/// Sequential Gauss-Seidel over the whole batch in its order, four constraints at a time where
/// `independent` (independentBlocks below) says a block of four consecutive constraints shares no
/// particle, one at a time elsewhere. Constraints without a common particle commute exactly, so
/// the result is the same bit for bit as gaussSeidelSweep (pbd_solvers.h).
void gaussSeidelLinksWide(DistanceBatch& batch, const std::vector<char>& independent, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level = bestSimdLevel());
void gaussSeidelVolumesWide(VolumeBatch& batch, const std::vector<char>& independent, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level = bestSimdLevel());

/// For each whole block of simd::kWidth consecutive constraints: 1 when no particle (pinned or
/// not) appears in two of its constraints. Depends only on the batch's particle indices.
template <class Batch>
std::vector<char> independentBlocks(const Batch& batch)
{
  constexpr std::size_t kWidth = static_cast<std::size_t>(simd::kWidth);
  std::vector<char> independent(batch.size() / kWidth, 0);
  for (std::size_t b = 0; b < independent.size(); ++b)
  {
    bool shared = false;
    for (std::size_t i = 0; i < kWidth && !shared; ++i)
    {
      const std::int32_t* p = batch.particles(b * kWidth + i);
      for (std::size_t j = i + 1; j < kWidth && !shared; ++j)
      {
        const std::int32_t* q = batch.particles(b * kWidth + j);
        for (int k = 0; k < Batch::Arity && !shared; ++k)
        {
          for (int l = 0; l < Batch::Arity; ++l)
          {
            shared = shared || p[k] == q[l];
          }
        }
      }
    }
    independent[b] = shared ? 0 : 1;
  }
  return independent;
}

} // namespace softbody

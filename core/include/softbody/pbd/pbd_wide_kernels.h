// The colored Gauss-Seidel solver's kernels, four constraints at a time (issue 15, item 2).
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

} // namespace softbody

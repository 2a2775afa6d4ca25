// Morton (Z-order) interleaving, shared by the vertex renumbering (mesh/reorder) and the point
// octree (collision/point_octree): both sort points along the same space-filling curve.
#pragma once

#include <cstdint>

namespace softbody
{

/// The 21 low bits of v spread to every third bit (bit i -> bit 3i), so that three of them
/// shifted by 0, 1 and 2 interleave into one 63-bit Morton code.
inline std::uint64_t spreadBits(std::uint64_t v)
{
  v &= 0x1fffffull;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

} // namespace softbody

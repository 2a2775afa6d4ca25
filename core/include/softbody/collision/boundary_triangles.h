// The surface of a tet mesh: the faces used by exactly one tet, oriented outward.
#pragma once

#include "softbody/common/geometry.h"

#include <array>
#include <cstdint>
#include <vector>

namespace softbody
{

/// The faces used by exactly one tet, each wound so that (b - a) x (c - a) points out of its
/// tet (the project's positive orientation, common/geometry.h, is assumed). In the order of
/// their tets, then of the faces opposite vertices 0..3. Faces shared by three or more tets
/// (a non-manifold mesh) are interior and left out like those shared by two.
std::vector<std::array<std::int32_t, 3>> boundaryTriangles(const std::vector<Tet>& tets);

} // namespace softbody

// Procedural tetrahedral meshes for tests, benchmarks and examples.
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <array>

namespace softbody
{

/// A box of nx * ny * nz cubes of edge `cellSize` [m] with its minimum corner at `origin`,
/// each cube split into the 6 Kuhn tets around its main diagonal (a conforming mesh; all tets
/// positively oriented). Points: (nx+1)(ny+1)(nz+1); tets: 6 nx ny nz.
/// The 6 Kuhn (Freudenthal) tets of a unit cube as corner offsets (0 or 1 per axis): each walks
/// from (0,0,0) to (1,1,1) one axis at a time. Neighbouring cubes split this way match face to
/// face; the orientation of each depends on the axis order (check it where it matters).
std::array<std::array<std::array<int, 3>, 4>, 6> kuhnCubeTets();

TetMesh makeTetBox(int nx, int ny, int nz, double cellSize, const Vec3& origin = Vec3::Zero());

} // namespace softbody

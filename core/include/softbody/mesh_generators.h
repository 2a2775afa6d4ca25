// Procedural tetrahedral meshes for tests, benchmarks and examples.
#pragma once

#include "softbody/tet_mesh.h"

namespace softbody
{

/// A box of nx * ny * nz cubes of edge `cellSize` [m] with its minimum corner at `origin`,
/// each cube split into the 6 Kuhn tets around its main diagonal (a conforming mesh; all tets
/// positively oriented). Points: (nx+1)(ny+1)(nz+1); tets: 6 nx ny nz.
TetMesh makeTetBox(int nx, int ny, int nz, double cellSize, const Vec3& origin = Vec3::Zero());

} // namespace softbody

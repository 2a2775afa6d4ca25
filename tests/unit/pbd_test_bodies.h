// Bodies the PBD/XPBD unit tests share.
#pragma once

#include "softbody/mesh/mesh_generators.h"
#include "softbody/scene/body.h"

namespace softbody::test
{

/// A cube of n x n x n cells (6 tets each) of the given size, density 1000 kg/m^3.
inline Body pbdBoxBody(int n, double cell, const Vec3& origin = Vec3::Zero())
{
  const TetMesh mesh = makeTetBox(n, n, n, cell, origin);
  Body body;
  body.mesh.points = mesh.points;
  body.mesh.tets = mesh.tets;
  body.material.physical.density = 1000.0;
  return body;
}

} // namespace softbody::test

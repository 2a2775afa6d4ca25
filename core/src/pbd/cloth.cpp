#include "softbody/pbd/cloth.h"

#include "softbody/common/errors.h"

namespace softbody
{

Body makeCloth(const ClothSpec& spec)
{
  const int nx = spec.particlesAlong1;
  const int ny = spec.particlesAlong2;
  if (nx < 2 || ny < 2)
  {
    throw InvalidInputError("A cloth needs at least 2 x 2 particles.");
  }
  if (!(spec.totalMass > 0.0) || !(spec.diagonalStiffness >= 0.0))
  {
    throw InvalidInputError("The cloth's mass must be positive and its diagonal stiffness non-negative.");
  }
  const Vec3 u = spec.point1 - spec.origin;
  const Vec3 v = spec.point2 - spec.origin;
  if (!(u.cross(v).norm() > 0.0))
  {
    throw InvalidInputError("Point1 and Point2 must span a plane with the origin.");
  }
  auto index = [nx](int i, int j) { return static_cast<std::int32_t>(j * nx + i); };

  Body body;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      body.mesh.points.push_back(spec.origin + (double(i) / (nx - 1)) * u + (double(j) / (ny - 1)) * v);
    }
  }
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      body.links.push_back({ index(i, j), index(i + 1, j) });
    }
  }
  for (int j = 0; j + 1 < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      body.links.push_back({ index(i, j), index(i, j + 1) });
    }
  }
  body.linkStiffnessScale.assign(body.links.size(), 1.0);
  if (spec.diagonalStiffness > 0.0)
  {
    for (int j = 0; j + 1 < ny; ++j)
    {
      for (int i = 0; i + 1 < nx; ++i)
      {
        body.links.push_back({ index(i, j), index(i + 1, j + 1) });
        body.links.push_back({ index(i + 1, j), index(i, j + 1) });
        body.linkStiffnessScale.push_back(spec.diagonalStiffness);
        body.linkStiffnessScale.push_back(spec.diagonalStiffness);
      }
    }
  }
  // Two triangles per cell, counter-clockwise seen from the side point1 x point2 points to:
  // what the cloth collides through (both sides: Body::surfaceTriangles).
  for (int j = 0; j + 1 < ny; ++j)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      body.surfaceTriangles.push_back({ index(i, j), index(i + 1, j), index(i + 1, j + 1) });
      body.surfaceTriangles.push_back({ index(i, j), index(i + 1, j + 1), index(i, j + 1) });
    }
  }
  body.pointMass.assign(body.mesh.points.size(), spec.totalMass / static_cast<double>(body.mesh.points.size()));
  body.pinned.assign(body.mesh.points.size(), 0);
  if (spec.pins != ClothPins::None)
  {
    body.pinned[static_cast<std::size_t>(index(0, ny - 1))] = 1;
    body.pinned[static_cast<std::size_t>(index(nx - 1, ny - 1))] = 1;
  }
  if (spec.pins == ClothPins::AllCorners)
  {
    body.pinned[static_cast<std::size_t>(index(0, 0))] = 1;
    body.pinned[static_cast<std::size_t>(index(nx - 1, 0))] = 1;
  }
  return body;
}

} // namespace softbody

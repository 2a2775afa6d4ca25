#include "softbody/collision/boundary_triangles.h"

#include <algorithm>
#include <tuple>

namespace softbody
{

std::vector<std::array<std::int32_t, 3>> boundaryTriangles(const std::vector<Tet>& tets)
{
  // Faces of a positive tet (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0, wound outward: for the unit
  // tet (0, e1, e2, e3) these give the normals (1,1,1), -e1, -e2, -e3.
  constexpr int kFaces[4][3] = { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };

  // Sorting the faces by their vertex set (rather than hashing) keeps the result independent
  // of any hash order; the duplicates of a set are then neighbours.
  struct FaceRecord
  {
    std::array<std::int32_t, 3> key; // sorted vertices
    std::int64_t slot;               // 4 * tet + face
  };
  std::vector<FaceRecord> faces;
  faces.reserve(tets.size() * 4);
  for (std::size_t t = 0; t < tets.size(); ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      std::array<std::int32_t, 3> key{ tets[t][kFaces[f][0]], tets[t][kFaces[f][1]], tets[t][kFaces[f][2]] };
      std::sort(key.begin(), key.end());
      faces.push_back({ key, static_cast<std::int64_t>(4 * t + f) });
    }
  }
  std::sort(faces.begin(), faces.end(), [](const FaceRecord& x, const FaceRecord& y) {
    return std::tie(x.key, x.slot) < std::tie(y.key, y.slot);
  });

  std::vector<std::int64_t> boundarySlots;
  for (std::size_t i = 0; i < faces.size();)
  {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key)
    {
      ++j;
    }
    if (j - i == 1)
    {
      boundarySlots.push_back(faces[i].slot);
    }
    i = j;
  }
  std::sort(boundarySlots.begin(), boundarySlots.end());

  std::vector<std::array<std::int32_t, 3>> triangles;
  triangles.reserve(boundarySlots.size());
  for (std::int64_t slot : boundarySlots)
  {
    const Tet& tet = tets[static_cast<std::size_t>(slot / 4)];
    const int* face = kFaces[slot % 4];
    triangles.push_back({ tet[face[0]], tet[face[1]], tet[face[2]] });
  }
  return triangles;
}

} // namespace softbody

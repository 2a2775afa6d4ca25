// The benchmark's meshes: generated boxes from ~1k to ~150k tets, and the public meshes of
// ../shared/data when present (read with VTK's readers and TetGen's own loader).
#pragma once

#include "softbody/mesh/tet_mesh.h"

#include <string>
#include <vector>

namespace softbody::bench
{

struct NamedMesh
{
  std::string name;
  TetMesh mesh;
};

std::vector<NamedMesh> generatedMeshes(bool smoke);

/// Meshes found under dataDir; prints a note for each one that is missing or unreadable.
std::vector<NamedMesh> sharedMeshes(const std::string& dataDir);

/// The generated meshes followed by the shared ones: what every benchmark runs on.
inline std::vector<NamedMesh> benchmarkMeshes(bool smoke, const std::string& dataDir)
{
  std::vector<NamedMesh> meshes = generatedMeshes(smoke);
  for (auto& m : sharedMeshes(dataDir))
  {
    meshes.push_back(std::move(m));
  }
  return meshes;
}

} // namespace softbody::bench

// The benchmark's meshes: generated boxes from ~1k to ~150k tets, and the public meshes of
// ../shared/data when present (read with VTK's readers and TetGen's own loader).
#pragma once

#include "softbody/massspring/mass_spring_settings.h"
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

/// The smoke runs' state-hash scene: the body 1 mm above a floor, strain limit 1.001, run for
/// kLandingTime. It lands at 14 ms (sqrt(2 mm / g)); on impact the limiter corrects springs.
/// `floor` / `strainLimit` switch the stages off to show that each acts.
constexpr double kLandingTime = 0.03;
SceneSettings landingScene(const TetMesh& mesh, bool floor = true, double strainLimit = 1.001);

/// Largest distance between corresponding points.
double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

} // namespace softbody::bench

// The benchmark's meshes: generated boxes from ~1k to ~150k tets, and the public meshes of
// ../shared/data when present (read with VTK's readers and TetGen's own loader).
#pragma once

#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/mesh/tet_mesh.h"

#include <array>
#include <cstdint>
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

/// Meshes found under dataDir; prints a note for each one that is missing or unreadable. The
/// smoke run reads the small ones only (PositionBasedDynamics and SOFA); the full run also IPC's
/// bunny (19k tets), sphere5K (28k) and Armadillo13K (55k).
std::vector<NamedMesh> sharedMeshes(const std::string& dataDir, bool smoke = false);

/// Real meshes as users make them: core's TetGen wrapper (TetGen's default quality, q 2.0) on
/// the public surfaces spot_triangulated.obj and (full run) bunny_10k.obj, and (full run) a
/// ~180k-tet TetGen mesh of an ellipsoid (ellipsoidMesh). Notes what it cannot find.
std::vector<NamedMesh> realMeshes(const std::string& dataDir, bool smoke);

/// A TetGen mesh of an ellipsoid of semi-axes 0.20 x 0.12 x 0.08 m (an icosphere of 5120
/// triangles, scaled), with TetGen's default quality and a volume bound chosen for about
/// `targetTets` tets. "ellipsoid180k": 180,000.
TetMesh ellipsoidMesh(double targetTets);

/// Reads a closed triangle surface from an OBJ file (v and f lines; polygons as fans).
void readObjSurface(const std::string& path, std::vector<Vec3>& points,
  std::vector<std::array<std::int32_t, 3>>& triangles);

/// One mesh by name or path: "ellipsoid180k" (or "ellipsoidNk" for N thousand tets), the name
/// of any benchmark mesh (e.g. "box_151200", "tetgen_bunny_10k", "Armadillo13K"), or a file:
/// TetGen .node/.ele (either, or their base), Gmsh .msh, or a closed .obj surface
/// (tetrahedralized here). Throws std::runtime_error when it finds none.
NamedMesh meshFromSpec(const std::string& spec, const std::string& dataDir);

/// The generated meshes followed by the shared and the real ones: what every benchmark runs on;
/// only the one `spec` names (meshFromSpec) when it is not empty.
std::vector<NamedMesh> benchmarkMeshes(bool smoke, const std::string& dataDir, const std::string& spec = {});

/// The generated box whose per-tet cost real meshes are compared with: the largest box of the
/// run (box_151200 in a full run); null when there is none.
const NamedMesh* referenceBox(const std::vector<NamedMesh>& meshes);

/// The smoke runs' state-hash scene: the body 1 mm above a floor, strain limit 1.001, run for
/// kLandingTime. It lands at 14 ms (sqrt(2 mm / g)); on impact the limiter corrects springs.
/// `floor` / `strainLimit` switch the stages off to show that each acts.
constexpr double kLandingTime = 0.03;
SceneSettings landingScene(const TetMesh& mesh, bool floor = true, double strainLimit = 1.001);

/// What a benchmark row says of a scene that blew up: "collapsed under its own weight (rho g H
/// / E = 12.5)" when the message says the body cannot carry its weight (material/self_weight.h;
/// the public meshes come in their authors' units, the IPC armadillo 115 units tall), else
/// `otherwise`.
std::string blowUpCause(const std::string& divergenceMessage, const std::string& otherwise);

/// Largest distance between corresponding points.
double maxDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

} // namespace softbody::bench

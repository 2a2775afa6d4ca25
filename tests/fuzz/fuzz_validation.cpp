// libFuzzer target: the path that turns user data into a refusal or a simulation, as the Soft
// Body filter drives it: a tet mesh (points, tets, pins, masses, links) and settings decoded
// from the input, then inspectTetMesh, prepareTetMesh, and the MassSpringSimulation and
// PbdSimulation constructors, and (when one is made) two steps of it. Setting up must end in a
// simulation or a softbody::InvalidInputError; stepping may also stop with
// softbody::SimulationDivergedError. Anything else (a crash, an ASan or UBSan-style report
// from ASan, another exception, a hang) is a finding.
#include "softbody/common/errors.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/tet_mesh.h"
#include "softbody/pbd/pbd_simulation.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace
{

using softbody::Vec3;

/// A double a user could type or a file could hold: mostly "interesting" values (zero, signs,
/// tiny, huge, NaN, infinities), sometimes any bit pattern, sometimes a plain range value.
double anyValue(FuzzedDataProvider& in, double typical)
{
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static const double special[] = { 0.0, -0.0, 1.0, -1.0, 0.5, 0.25, 2.0, 1e-300, 1e-12, 1e-6,
    1e3, 1e9, 1e300, std::numeric_limits<double>::max(), std::numeric_limits<double>::denorm_min(),
    std::numeric_limits<double>::quiet_NaN(), kInf, -kInf };
  switch (in.ConsumeIntegralInRange<int>(0, 3))
  {
    case 0: return typical;
    case 1: return special[in.ConsumeIntegralInRange<std::size_t>(0, std::size(special) - 1)];
    case 2: return in.ConsumeFloatingPointInRange<double>(-4.0 * std::abs(typical), 4.0 * std::abs(typical));
    default: return in.ConsumeFloatingPoint<double>();
  }
}

Vec3 anyVec(FuzzedDataProvider& in, const Vec3& typical)
{
  return { anyValue(in, typical.x()), anyValue(in, typical.y()), anyValue(in, typical.z()) };
}

struct Body
{
  std::vector<Vec3> points;
  std::vector<softbody::Tet> tets;
  std::vector<std::array<std::int32_t, 2>> links;
  std::vector<char> pinned;
  std::vector<double> pointMass;
};

Body makeBody(FuzzedDataProvider& in)
{
  Body b;
  // Points on a small integer grid times a scale (so that valid, inverted, degenerate and
  // sliver tets all occur), some with any coordinate at all.
  const double scale = anyValue(in, 0.1);
  const std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, 24);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (in.ConsumeIntegralInRange<int>(0, 15) == 0)
    {
      b.points.push_back(anyVec(in, { 0.0, 0.0, 0.0 }));
      continue;
    }
    const int x = in.ConsumeIntegralInRange<int>(-2, 2), y = in.ConsumeIntegralInRange<int>(-2, 2),
              z = in.ConsumeIntegralInRange<int>(-2, 2);
    b.points.push_back(Vec3(x, y, z) * scale);
  }
  const auto index = [&]() -> std::int32_t {
    if (in.ConsumeIntegralInRange<int>(0, 31) == 0)
      return in.ConsumeIntegral<std::int32_t>();
    return in.ConsumeIntegralInRange<std::int32_t>(0, static_cast<std::int32_t>(n)) - (n ? 0 : 1);
  };
  const std::size_t tets = in.ConsumeIntegralInRange<std::size_t>(0, 24);
  for (std::size_t t = 0; t < tets; ++t)
  {
    b.tets.push_back({ index(), index(), index(), index() });
  }
  const std::size_t links = in.ConsumeIntegralInRange<std::size_t>(0, 3) == 0
    ? in.ConsumeIntegralInRange<std::size_t>(0, 16) : 0;
  for (std::size_t l = 0; l < links; ++l)
  {
    b.links.push_back({ index(), index() });
  }
  // Per-point arrays: absent, one per point, or (rarely) of the wrong length.
  const auto length = [&]() -> std::size_t {
    switch (in.ConsumeIntegralInRange<int>(0, 7))
    {
      case 0: return n + 1;
      case 1: return n > 0 ? n - 1 : 0;
      case 2: case 3: return n;
      default: return 0;
    }
  };
  for (std::size_t i = 0, m = length(); i < m; ++i)
  {
    b.pinned.push_back(static_cast<char>(in.ConsumeIntegralInRange<int>(0, 7) == 0));
  }
  for (std::size_t i = 0, m = length(); i < m; ++i)
  {
    b.pointMass.push_back(anyValue(in, 0.01));
  }
  return b;
}

template <typename E>
E anyEnum(FuzzedDataProvider& in, int count)
{
  return static_cast<E>(in.ConsumeIntegralInRange<int>(0, count - 1));
}

/// Two steps at most, and never an end time that is not finite (the filter's EndTime is
/// checked to be finite): stepping is part of the contract but must not make the target slow.
void stepTwice(softbody::Simulation& simulation)
{
  const double h = simulation.stepSize();
  double end = 2.0 * h;
  if (!std::isfinite(end) || end > 1.0)
    end = std::min(h, 1.0);
  try
  {
    simulation.advance(end);
  }
  catch (const softbody::SimulationDivergedError&)
  {
  }
}

void massSpring(FuzzedDataProvider& in, const Body& b)
{
  softbody::Body body;
  body.mesh.points = b.points;
  body.mesh.tets = b.tets;
  body.pinned = b.pinned;
  softbody::MaterialSettings& m = body.material;
  m.mode = anyEnum<softbody::MaterialMode>(in, 2);
  m.physical.youngsModulus = anyValue(in, 1e5);
  m.physical.poissonRatio = anyValue(in, 0.3);
  m.physical.density = anyValue(in, 1100.0);
  m.physical.dampingTime = anyValue(in, 2e-3);
  m.raw.distanceStiffness = anyValue(in, 100.0);
  m.raw.distanceDamping = anyValue(in, 0.1);
  m.raw.volumeStiffness = anyValue(in, 100.0);
  m.raw.volumeDamping = anyValue(in, 0.1);
  m.raw.totalMass = anyValue(in, 1.0);
  m.massDistribution = anyEnum<softbody::MassDistribution>(in, 2);
  m.maxInverseMass = in.ConsumeBool() ? 0.0 : anyValue(in, 10.0);

  softbody::SceneSettings s;
  s.integrator = anyEnum<softbody::Integrator>(in, 4);
  s.timeStep = in.ConsumeBool() ? 0.0 : anyValue(in, 1e-3);
  s.gravity = anyVec(in, { 0.0, 0.0, -9.81 });
  s.floorEnabled = in.ConsumeBool();
  s.floor.origin = anyVec(in, { 0.0, 0.0, 0.0 });
  s.floor.normal = anyVec(in, { 0.0, 0.0, 1.0 });
  s.strainLimit = in.ConsumeBool() ? 0.0 : anyValue(in, 1.1);
  s.strainLimitIterations = in.ConsumeIntegralInRange<int>(-1, 8);
  s.invertedTets = anyEnum<softbody::InvertedTetPolicy>(in, 2);
  try
  {
    softbody::MassSpringSimulation simulation(std::move(body), s);
    stepTwice(simulation);
  }
  catch (const softbody::InvalidInputError&)
  {
  }
}

void pbd(FuzzedDataProvider& in, const Body& b)
{
  softbody::Body body;
  body.points = b.points;
  body.tets = b.tets;
  body.links = b.links;
  body.pinned = b.pinned;
  body.pointMass = b.pointMass;
  if (in.ConsumeBool())
  {
    for (std::size_t i = 0; i < b.links.size(); ++i)
      body.linkStiffnessScale.push_back(anyValue(in, 1.0));
  }
  body.material.physical.density = anyValue(in, 1000.0);
  body.material.massDistribution = anyEnum<softbody::MassDistribution>(in, 2);

  softbody::PbdSettings s;
  s.formulation = anyEnum<softbody::PbdFormulation>(in, 2);
  s.solver = anyEnum<softbody::PbdSolver>(in, 3);
  s.prediction = anyEnum<softbody::PbdPrediction>(in, 2);
  s.timeStep = in.ConsumeBool() ? 0.0 : anyValue(in, 1e-3);
  s.substeps = in.ConsumeIntegralInRange<int>(-1, 3);
  s.iterations = in.ConsumeIntegralInRange<int>(-1, 4);
  s.residualTolerance = in.ConsumeBool() ? 0.0 : anyValue(in, 1e-6);
  s.relaxation = anyValue(in, 1.0);
  s.gravity = anyVec(in, { 0.0, 0.0, -9.81 });
  s.damping = in.ConsumeBool() ? 0.0 : anyValue(in, 0.1);
  s.floorEnabled = in.ConsumeBool();
  s.floor.origin = anyVec(in, { 0.0, 0.0, 0.0 });
  s.floor.normal = anyVec(in, { 0.0, 0.0, 1.0 });
  s.particleRadius = in.ConsumeBool() ? 0.0 : anyValue(in, 0.01);
  s.collisions.staticFriction = in.ConsumeBool() ? 0.0 : anyValue(in, 0.5);
  s.collisions.dynamicFriction = in.ConsumeBool() ? 0.0 : anyValue(in, 0.5);
  s.collisions.restitution = in.ConsumeBool() ? 0.0 : anyValue(in, 0.5);
  s.links = { anyValue(in, 1.0), anyValue(in, 1e-4) };
  s.volumes = { anyValue(in, 1.0), anyValue(in, 1e-10) };
  s.attachments = { anyValue(in, 1.0), in.ConsumeBool() ? 0.0 : anyValue(in, 1e-6) };
  s.elasticFromMaterial = in.ConsumeBool();
  body.material.physical.youngsModulus = anyValue(in, 1e5);
  body.material.physical.poissonRatio = anyValue(in, 0.3);
  s.breakingStrain = in.ConsumeBool() ? 0.0 : anyValue(in, 0.5);
  s.plasticYield = in.ConsumeBool() ? 0.0 : anyValue(in, 0.1);
  s.plasticCreep = in.ConsumeBool() ? 0.0 : anyValue(in, 1.0);
  s.invertedTets = anyEnum<softbody::InvertedTetPolicy>(in, 2);
  try
  {
    softbody::PbdSimulation simulation(std::move(body), s);
    stepTwice(simulation);
  }
  catch (const softbody::InvalidInputError&)
  {
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  FuzzedDataProvider in(data, size);
  const int method = in.ConsumeIntegralInRange<int>(0, 2);
  const Body body = makeBody(in);

  // The mesh checks on their own, with any thresholds: never a crash, never an exception.
  softbody::TetMesh mesh{ body.points, body.tets };
  (void)softbody::inspectTetMesh(mesh, anyValue(in, softbody::kDegenerateRelativeVolume),
    anyValue(in, softbody::kMinDihedralDegrees));
  try
  {
    std::vector<std::string> warnings;
    (void)softbody::prepareTetMesh(mesh, anyEnum<softbody::InvertedTetPolicy>(in, 2), warnings);
  }
  catch (const softbody::InvalidInputError&)
  {
  }

  if (method == 0)
    massSpring(in, body);
  else
    pbd(in, body);
  return 0;
}

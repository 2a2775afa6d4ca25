// Internal forces: zero at rest, conservative (minus the energy gradient), momentum-free.
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace softbody;

namespace
{

struct Body
{
  TetMesh mesh;
  Topology topology;
  ElementConstants constants;
};

Body makeBody(const MaterialSettings& material, int n = 3)
{
  Body body;
  body.mesh = makeTetBox(n, n + 1, n, 0.1);
  body.topology = buildTopology(body.mesh.points.size(), body.mesh.tets);
  std::vector<std::string> warnings;
  body.constants = computeElementConstants(body.topology, body.mesh.points, material, warnings);
  return body;
}

MaterialSettings rubber(double poisson = 0.45, double damping = 1e-3)
{
  MaterialSettings m;
  m.physical.poissonRatio = poisson;
  m.physical.dampingTime = damping;
  return m;
}

std::vector<Vec3> forcesAt(const Body& body, const std::vector<Vec3>& x, const std::vector<Vec3>& v)
{
  ForceScratch scratch;
  std::vector<Vec3> f;
  computeInternalForces(body.topology, body.constants, x, v, scratch, f);
  return f;
}

double maxNorm(const std::vector<Vec3>& f)
{
  double m = 0.0;
  for (const Vec3& v : f)
  {
    m = std::max(m, v.norm());
  }
  return m;
}

} // namespace

TEST(Forces, RestShapeAtRestFeelsNoForce)
{
  const Body body = makeBody(rubber());
  const std::vector<Vec3> zero(body.mesh.points.size(), Vec3::Zero());
  const double scale = body.constants.springStiffness[0] * 0.1; // force of a 100% stretch
  EXPECT_LT(maxNorm(forcesAt(body, body.mesh.points, zero)), 1e-12 * scale);
}

TEST(Forces, ElasticForcesAreMinusTheEnergyGradient)
{
  const Body body = makeBody(rubber(0.45, 0.0), 2);
  const std::vector<Vec3> x = test::jitter(body.mesh.points, 0.02);
  const std::vector<Vec3> zero(x.size(), Vec3::Zero());
  const std::vector<Vec3> f = forcesAt(body, x, zero);
  const double eps = 1e-7;
  for (std::size_t i = 0; i < x.size(); i += 5)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      auto plus = x, minus = x;
      plus[i][axis] += eps;
      minus[i][axis] -= eps;
      const double gradient = (elasticEnergy(body.topology, body.constants, plus) -
                                elasticEnergy(body.topology, body.constants, minus)) / (2 * eps);
      EXPECT_NEAR(f[i][axis], -gradient, 1e-5 * (1.0 + std::abs(gradient))) << "point " << i;
    }
  }
}

TEST(Forces, InternalForcesConserveLinearAndAngularMomentum)
{
  // Deformed and moving: springs, volumes and both damping terms all act.
  const Body body = makeBody(rubber(0.45, 5e-3));
  const std::vector<Vec3> x = test::jitter(body.mesh.points, 0.03);
  const std::vector<Vec3> v = test::randomVectors(x.size(), 2.0);
  const std::vector<Vec3> f = forcesAt(body, x, v);
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    force += f[i];
    torque += x[i].cross(f[i]);
  }
  const double scale = maxNorm(f);
  ASSERT_GT(scale, 1.0);
  EXPECT_LT(force.norm(), 1e-11 * scale * double(x.size()));
  EXPECT_LT(torque.norm(), 1e-11 * scale * double(x.size()));
}

TEST(Forces, CompressedTetIsPushedBackTowardItsRestVolume)
{
  // One tet, springs off, volume term only: every corner force points along dV/dp, so the
  // instantaneous volume rate of the resulting motion (dV/dt = sum g_i . w f_i dt) is positive.
  MaterialSettings raw;
  raw.mode = MaterialMode::Raw;
  raw.raw = { 0.0, 0.0, 50.0, 0.0, 1.0 };
  TetMesh mesh;
  mesh.points = { Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1) };
  mesh.tets = { { 0, 1, 2, 3 } };
  const Topology topology = buildTopology(4, mesh.tets);
  std::vector<std::string> warnings;
  const ElementConstants c = computeElementConstants(topology, mesh.points, raw, warnings);

  std::vector<Vec3> compressed = mesh.points;
  compressed[3].z() = 0.5; // V = V0 / 2
  ForceScratch scratch;
  std::vector<Vec3> f;
  computeInternalForces(topology, c, compressed, std::vector<Vec3>(4, Vec3::Zero()), scratch, f);
  const auto g = tetVolumeGradients(compressed[0], compressed[1], compressed[2], compressed[3]);
  double volumeRate = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_GT(f[k].dot(g[k]), 0.0) << "corner " << k;
    volumeRate += f[k].dot(g[k]);
  }
  // Magnitude: f_i = -(k_V / V0^2)(V - V0) g_i, so sum f.g = (k_V / V0^2)(V0 / 2) sum |g|^2.
  double gradientSquares = 0.0;
  for (const Vec3& gi : g)
  {
    gradientSquares += gi.squaredNorm();
  }
  const double v0 = 1.0 / 6.0;
  EXPECT_NEAR(volumeRate, 50.0 / (v0 * v0) * (v0 / 2) * gradientSquares, 1e-9 * volumeRate);
}

TEST(Forces, SpringDampingOpposesRelativeVelocityOnly)
{
  const Body body = makeBody(rubber(0.3, 1e-2), 2);
  // A rigid translation has no relative velocity: no damping force at the rest shape.
  const std::vector<Vec3> drift(body.mesh.points.size(), Vec3(0.3, -1.0, 2.0));
  const double scale = body.constants.springStiffness[0] * 0.1;
  EXPECT_LT(maxNorm(forcesAt(body, body.mesh.points, drift)), 1e-12 * scale);
  // Expansion velocity v = s x: damping pulls inward, so forces do negative power.
  const std::vector<Vec3> expansion = body.mesh.points; // v = 1/s * x
  const std::vector<Vec3> f = forcesAt(body, body.mesh.points, expansion);
  double power = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    power += f[i].dot(expansion[i]);
  }
  EXPECT_LT(power, 0.0);
}

TEST(Forces, VolumeDampingDissipatesExactlyItsRateSquared)
{
  // Raw constants with volume damping only (no springs, no volume stiffness): at the rest shape
  // the forces are f_i = sum_t s_t dV_t/dp_i with s_t = -k_V,d' dV_t/dt, so their power is
  // sum f.v = -sum_t k_V,d' (dV_t/dt)^2 <= 0, exactly. A random velocity field is used.
  MaterialSettings material;
  material.mode = MaterialMode::Raw;
  material.raw = { 0.0, 0.0, 0.0, 2.0, 1.0 };
  const Body body = makeBody(material, 2);
  const std::vector<Vec3> v = test::randomVectors(body.mesh.points.size(), 1.0);
  const std::vector<Vec3> f = forcesAt(body, body.mesh.points, v);
  double power = 0.0, expected = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    power += f[i].dot(v[i]);
  }
  for (std::size_t t = 0; t < body.topology.tets.size(); ++t)
  {
    const Tet& tet = body.topology.tets[t];
    const auto g = tetVolumeGradients(body.mesh.points[tet[0]], body.mesh.points[tet[1]],
      body.mesh.points[tet[2]], body.mesh.points[tet[3]]);
    double rate = 0.0;
    for (int k = 0; k < 4; ++k)
    {
      rate += g[k].dot(v[tet[k]]);
    }
    expected -= body.constants.volumeDamping[t] * rate * rate;
  }
  ASSERT_LT(expected, 0.0);
  EXPECT_NEAR(power / expected, 1.0, 1e-12);
}

// PBD/XPBD at the floor: bodies that start below it, and restitution of tet bodies.
#include "softbody/mesh/mesh_generators.h"
#include "softbody/pbd/pbd_simulation.h"
#include "pbd_test_bodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace softbody
{
namespace
{
Body boxBody(int n, double cell, const Vec3& origin)
{
  Body body = test::pbdBoxBody(n, cell, origin);
  body.material.physical.youngsModulus = 1e6; // read by XPBD (floorSettings), not by PBD
  return body;
}

struct Motion
{
  double z = 0.0; ///< centre of mass height [m]
  double vz = 0.0; ///< its vertical speed [m/s]
};

Motion centreOfMass(const PbdSimulation& sim)
{
  Motion m;
  double total = 0.0;
  for (std::size_t i = 0; i < sim.positions().size(); ++i)
  {
    const double mass = 1.0 / sim.inverseMasses()[i];
    m.z += mass * sim.positions()[i].z();
    m.vz += mass * sim.velocities()[i].z();
    total += mass;
  }
  m.z /= total;
  m.vz /= total;
  return m;
}

PbdSettings floorSettings(PbdFormulation formulation)
{
  PbdSettings settings;
  settings.formulation = formulation;
  settings.floorEnabled = true;
  settings.timeStep = 1e-3;
  if (formulation == PbdFormulation::Xpbd)
  {
    settings.elasticFromMaterial = true; // E = 1 MPa (boxBody), nu = 0.3
  }
  return settings;
}

TEST(PbdFloor, BodyStartingBelowTheFloorIsLiftedWithoutVelocity)
{
  // A 0.2 m cube centred on the floor plane (half of it below). Without pre-stabilization the
  // floor projection would flatten the lower half and the constraints throw it up (PBD: 2.5 m/s).
  for (PbdFormulation formulation : { PbdFormulation::Pbd, PbdFormulation::Xpbd })
  {
    PbdSimulation sim(boxBody(4, 0.05, Vec3(-0.1, -0.1, -0.1)), floorSettings(formulation));
    const bool warned = std::any_of(sim.warnings().begin(), sim.warnings().end(),
      [](const std::string& w) { return w.find("points start below the floor") != std::string::npos; });
    EXPECT_TRUE(warned);
    double lowest = 1e9;
    for (const Vec3& p : sim.positions())
    {
      lowest = std::min(lowest, p.z());
    }
    // Lifted at construction onto the floor's contact thickness (the margin: tet vertices
    // have no radius), where the contact solve keeps it.
    const double margin = sim.collisionDetector()->margin();
    EXPECT_GT(margin, 0.0);
    EXPECT_NEAR(lowest, margin, 1e-12);
    const double start = centreOfMass(sim).z;
    EXPECT_NEAR(start, 0.1 + margin, 1e-12);
    double maxUp = 0.0, maxZ = start;
    for (int s = 0; s < 1000; ++s)
    {
      sim.step(1e-3);
      const Motion m = centreOfMass(sim);
      maxUp = std::max(maxUp, m.vz);
      maxZ = std::max(maxZ, m.z);
      for (const Vec3& v : sim.velocities())
      {
        maxUp = std::max(maxUp, v.z());
      }
    }
    std::printf("formulation %d: max upward point speed %.3g m/s, max rise %.3g m\n",
      int(formulation), maxUp, maxZ - start);
    EXPECT_LT(maxUp, 0.5) << int(formulation);
    EXPECT_LT(maxZ, start + 1e-3) << int(formulation);
    EXPECT_NEAR(centreOfMass(sim).z, start, 0.01) << int(formulation); // rests on the floor
  }
}

/// Height the centre of mass of a 0.1 m cube reaches after bouncing, above where it rests,
/// when dropped with its bottom 0.3 m above the floor: it falls h = 0.3 m - the contact
/// margin (where it rests), returned in `fall`.
double reboundHeight(PbdFormulation formulation, double restitution, double& fall, int substeps = 1)
{
  PbdSettings settings = floorSettings(formulation);
  settings.collisions.restitution = restitution;
  settings.substeps = substeps;
  PbdSimulation sim(boxBody(2, 0.05, Vec3(0, 0, 0.3)), settings);
  fall = 0.3 - sim.collisionDetector()->margin();
  const double resting = centreOfMass(sim).z - fall;
  bool bounced = false;
  double top = 0.0;
  for (int s = 0; s < 1500; ++s)
  {
    sim.step(1e-3);
    const Motion m = centreOfMass(sim);
    if (!bounced && m.vz > 0.0 && m.z < resting + 0.05)
    {
      bounced = true;
    }
    if (bounced)
    {
      top = std::max(top, m.z);
      if (m.vz < 0.0)
      {
        break;
      }
    }
  }
  return bounced ? top - resting : 0.0;
}

TEST(PbdFloor, RestitutionMakesTetBodiesBounce)
{
  // Without the body-level restitution the rebound would be the same for every e. Rigid-body
  // bounce: e^2 h.
  for (PbdFormulation formulation : { PbdFormulation::Pbd, PbdFormulation::Xpbd })
  {
    double h = 0.0;
    const double none = reboundHeight(formulation, 0.0, h);
    const double half = reboundHeight(formulation, 0.5, h);
    const double full = reboundHeight(formulation, 1.0, h);
    std::printf("formulation %d: rebound %.4g m (e = 0), %.4g m (e = 0.5, e^2 h = %.4g), %.4g m "
                "(e = 1, h = %.4g)\n",
      int(formulation), none, half, 0.25 * h, full, h);
    // e = 0 keeps what the body's own elasticity gives back (XPBD, E = 1 MPa: 1.5 cm).
    EXPECT_LT(none, 0.02) << int(formulation);
    EXPECT_GT(half, 3.0 * none) << int(formulation);
    EXPECT_NEAR(half, 0.25 * h, 0.2 * 0.25 * h) << int(formulation);
    EXPECT_NEAR(full, h, 0.2 * h) << int(formulation);
    EXPECT_LE(full, h * 1.01) << int(formulation); // never gains energy
  }
}

} // namespace
} // namespace softbody

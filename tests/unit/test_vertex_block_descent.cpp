// Vertex Block Descent (vertex_block_descent.h): the sweeps converge to Implicit Euler's answer
// (the same backward-Euler equations) for every material model, with pinned points; a body
// landing on the floor stays on it with its tets right side out; the states are bitwise the
// same at 1 and 2 threads; the points of one color share no element.
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/massspring/vertex_block_descent.h"
#include "softbody/mesh/graph_coloring.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace softbody;

TEST(VertexBlockDescent, ColorsSeparateEveryEdge)
{
  const TetMesh mesh = makeTetBox(5, 4, 3, 0.1);
  const Topology topology = buildTopology(mesh.points.size(), mesh.tets);
  const Coloring colors = colorVertices(topology);
  std::vector<int> colorOf(topology.vertexCount, -1);
  for (std::size_t c = 0; c < colors.colorCount(); ++c)
  {
    for (auto k = colors.colorOffsets[c]; k < colors.colorOffsets[c + 1]; ++k)
    {
      colorOf[static_cast<std::size_t>(colors.order[static_cast<std::size_t>(k)])] = static_cast<int>(c);
    }
  }
  EXPECT_EQ(std::count(colorOf.begin(), colorOf.end(), -1), 0);
  for (const Edge& edge : topology.edges)
  {
    EXPECT_NE(colorOf[static_cast<std::size_t>(edge.a)], colorOf[static_cast<std::size_t>(edge.b)]);
  }
  EXPECT_GE(colors.colorCount(), 4u); // a tet's four corners need four
}

// One step of 1/60 s from a jittered, moving state of a box pinned at one face: the sweeps'
// answer approaches Newton's as their number grows, for every material model, plain and
// Chebyshev-accelerated.
TEST(VertexBlockDescent, ConvergesToImplicitEulerForEveryMaterialModel)
{
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated, MaterialModel::StableNeoHookean })
  {
    Body body;
    body.mesh = makeTetBox(4, 3, 3, 0.05);
    body.material.model = model;
    body.pinned.assign(body.mesh.points.size(), 0);
    for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
    {
      body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
    }
    DynamicState start;
    start.positions = test::jitter(body.mesh.points, 0.004);
    start.velocities = test::randomVectors(start.positions.size(), 0.5);
    for (std::size_t i = 0; i < start.positions.size(); ++i)
    {
      if (body.pinned[i])
      {
        start.positions[i] = body.mesh.points[i];
        start.velocities[i].setZero();
      }
    }
    SceneSettings scene;
    scene.timeStep = 1.0 / 60.0;
    scene.integrator = Integrator::ImplicitEuler;
    scene.implicit.tolerance = 1e-7; // about the floor of double precision for this body
    scene.implicit.maxIterations = 100;
    MassSpringSimulation newton(body, scene);
    newton.restoreState(start);
    newton.advance(scene.timeStep);
    ASSERT_TRUE(newton.implicitConvergence()->converged) << materialModelName(model);

    scene.integrator = Integrator::VertexBlockDescent;
    scene.implicit.tolerance = 0.0; // a fixed number of sweeps
    for (double radius : { 0.0, 0.95 }) // plain sweeps, and Chebyshev-accelerated
    {
      scene.implicit.chebyshevRadius = radius;
      std::vector<double> errors;
      for (int sweeps : { 1, 4, 16, 64, 256 })
      {
        scene.implicit.maxIterations = sweeps;
        MassSpringSimulation vbd(body, scene);
        vbd.restoreState(start);
        vbd.advance(scene.timeStep);
        errors.push_back(test::maxDistance(vbd.positions(), newton.positions()));
        for (std::size_t i = 0; i < start.positions.size(); ++i)
        {
          if (body.pinned[i])
          {
            ASSERT_EQ(vbd.positions()[i], body.mesh.points[i]) << "a pinned point moved";
          }
        }
      }
      std::cout << materialModelName(model) << ", Chebyshev radius " << radius
                << ": largest distance to Newton's answer after 1, 4, 16, 64, 256 sweeps:";
      for (double e : errors)
      {
        std::cout << ' ' << e;
      }
      std::cout << " m\n";
      // Each count closer than the last, until Newton's own answer's error (tolerance 1e-7:
      // about 1e-9 m here) is reached.
      for (std::size_t k = 1; k < errors.size(); ++k)
      {
        EXPECT_TRUE(errors[k] < errors[k - 1] || errors[k] < 1e-8)
          << materialModelName(model) << ", radius " << radius << ", step " << k << ": " << errors[k] << " after " << errors[k - 1];
      }
      EXPECT_LT(errors.back(), 1e-3 * errors.front()) << materialModelName(model) << ", radius " << radius;
    }
  }
}

// With a tolerance the sweeps stop at the residual as Newton does, and a body dropped 3 cm onto
// the floor lands and rests on it with no tet inverted, for a soft and a stiff material.
TEST(VertexBlockDescent, ABodyLandsOnTheFloorAndRests)
{
  for (double youngs : { 1e5, 1e7 })
  {
    Body body;
    body.mesh = makeTetBox(5, 4, 3, 0.04, Vec3(0, 0, 0.03));
    body.material.model = MaterialModel::StableNeoHookean;
    body.material.physical.youngsModulus = youngs;
    SceneSettings scene;
    scene.integrator = Integrator::VertexBlockDescent;
    scene.floorEnabled = true;
    scene.implicit.tolerance = 1e-3;
    scene.implicit.maxIterations = 500;
    MassSpringSimulation sim(body, scene);
    for (int frame = 1; frame <= 30; ++frame)
    {
      sim.advance(frame / 30.0);
    }
    double lowest = 1e300, speedSquared = 0.0;
    for (std::size_t i = 0; i < sim.positions().size(); ++i)
    {
      lowest = std::min(lowest, sim.positions()[i].z());
      speedSquared += sim.velocities()[i].squaredNorm() / static_cast<double>(sim.positions().size());
    }
    EXPECT_GT(lowest, -1e-6) << "E " << youngs;
    EXPECT_LT(lowest, 0.01) << "E " << youngs << ": it should be resting on the floor";
    // At rest after 1 s: what kinetic energy is left is under 1 % of what the 3 cm drop gave.
    EXPECT_LT(0.5 * speedSquared, 0.01 * 9.81 * 0.03) << "E " << youngs;
    const std::vector<double> ratios = sim.tetVolumeRatios();
    EXPECT_GT(*std::min_element(ratios.begin(), ratios.end()), 0.0) << "E " << youngs << ": a tet inverted";
  }
}

// Chebyshev acceleration reaches the tolerance in fewer sweeps than plain sweeps on a soft box
// resting on the floor at 1/30 s steps, at the same rest state (within what the tolerance
// allows); a radius outside [0, 1) is refused, quoting it.
TEST(VertexBlockDescent, ChebyshevAccelerationNeedsFewerSweepsForTheSameRestState)
{
  Body body;
  body.mesh = makeTetBox(6, 6, 4, 0.025, Vec3(0, 0, 0.001));
  body.material.physical.youngsModulus = 1e4;
  SceneSettings scene;
  scene.integrator = Integrator::VertexBlockDescent;
  scene.floorEnabled = true;
  scene.timeStep = 1.0 / 30.0;
  scene.implicit.maxIterations = 2000;
  unsigned long long sweeps[2] = { 0, 0 };
  std::vector<Vec3> rest[2];
  for (int accelerated : { 0, 1 })
  {
    scene.implicit.chebyshevRadius = accelerated ? 0.95 : 0.0;
    MassSpringSimulation sim(body, scene);
    sim.advance(0.5);
    ASSERT_EQ(sim.implicitConvergence()->unconvergedSteps, 0u) << "radius " << scene.implicit.chebyshevRadius;
    sweeps[accelerated] = sim.implicitConvergence()->iterationsTotal;
    rest[accelerated] = sim.positions();
  }
  std::cout << "sweeps over 0.5 s: plain " << sweeps[0] << ", Chebyshev (0.95) " << sweeps[1] << "\n";
  EXPECT_LT(2 * sweeps[1], sweeps[0]);
  EXPECT_LT(test::maxDistance(rest[0], rest[1]), 1e-3 * 0.15);
  scene.implicit.chebyshevRadius = 1.0;
  try
  {
    MassSpringSimulation refused(body, scene);
    ADD_FAILURE() << "a Chebyshev radius of 1 was accepted";
  }
  catch (const std::exception& error)
  {
    EXPECT_NE(std::string(error.what()).find("Chebyshev"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find('1'), std::string::npos) << error.what();
  }
}

TEST(VertexBlockDescent, ResultsDoNotDependOnTheThreadCount)
{
  std::vector<Vec3> positions[2];
  for (std::size_t threads : { 1u, 2u })
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Body body;
    body.mesh = makeTetBox(5, 4, 3, 0.03, Vec3(0, 0, 0.02));
    body.material.model = MaterialModel::Corotated;
    SceneSettings scene;
    scene.integrator = Integrator::VertexBlockDescent;
    scene.floorEnabled = true;
    MassSpringSimulation sim(body, scene);
    for (int frame = 1; frame <= 6; ++frame)
    {
      sim.advance(frame / 30.0);
    }
    positions[threads - 1] = sim.positions();
  }
  EXPECT_EQ(positions[0], positions[1]);
}

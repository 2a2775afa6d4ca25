// The coordinate preconditioner of Newton's conjugate gradients (coordinate_preconditioner.h):
// its matrix is the step's isotropic stiffness plus inertia, it leaves the solution of every
// implicit solve as it was (to the solve's tolerance) while cutting CG iterations where block
// Jacobi needs many (a steel cantilever), it refactors only when the step or the held points
// change, and its results do not depend on the thread count. The same for each approximate
// inverse of its matrix that sees the whole mesh: the complete Cholesky factor and, where the
// build has hypre, the algebraic multigrid V-cycle (amg_preconditioner.h).
#include "softbody/common/errors.h"
#include "softbody/massspring/amg_preconditioner.h"
#include "softbody/massspring/coordinate_matrix.h"
#include "softbody/massspring/coordinate_preconditioner.h"
#include "softbody/massspring/mass_spring_setup.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>

using namespace softbody;

namespace
{

/// A 10 x 2 x 2 cantilever of 2 cm cells, pinned at x = 0.
Body cantilever(MaterialModel model, double youngsModulus)
{
  Body body;
  body.mesh = makeTetBox(10, 2, 2, 0.02, Vec3(0, 0, 1));
  body.material.model = model;
  body.material.physical.youngsModulus = youngsModulus;
  body.material.physical.poissonRatio = 0.3;
  body.material.physical.density = 7850.0;
  body.pinned.assign(body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
  }
  return body;
}

/// The preconditioners on A that see the whole mesh, in this build.
std::vector<LinearPreconditioner> wholeMeshKinds()
{
  if (algebraicMultigridAvailable())
  {
    return { LinearPreconditioner::Coordinate, LinearPreconditioner::AlgebraicMultigrid };
  }
  return { LinearPreconditioner::Coordinate };
}

const char* kindName(LinearPreconditioner kind)
{
  switch (kind)
  {
    case LinearPreconditioner::BlockJacobi: return "block Jacobi";
    case LinearPreconditioner::Coordinate: return "complete Cholesky";
    case LinearPreconditioner::IncompleteCoordinate: return "incomplete Cholesky";
    case LinearPreconditioner::AlgebraicMultigrid: return "algebraic multigrid";
  }
  return "?";
}

struct SolveRun
{
  std::vector<Vec3> positions;
  double cgPerNewton = 0.0;
  int factorizations = 0;
  std::size_t warnings = 0;
};

SolveRun run(const Body& body, Integrator integrator, LinearPreconditioner preconditioner,
  double step, int steps)
{
  SceneSettings scene;
  scene.integrator = integrator;
  scene.timeStep = step;
  scene.implicit.tolerance = 1e-9;
  scene.implicit.preconditioner = preconditioner;
  MassSpringSimulation sim(body, scene);
  sim.advance(steps * step);
  SolveRun r;
  r.positions = sim.positions();
  const ImplicitConvergence& c = *sim.implicitConvergence();
  r.cgPerNewton = double(c.linearIterationsTotal) / double(c.iterationsTotal);
  r.warnings = sim.warnings().size();
  if (const CoordinatePreconditioner* p = sim.coordinatePreconditioner())
  {
    r.factorizations = p->factorizations();
  }
  return r;
}

} // namespace

// Without pins, a translation of the whole body stretches nothing: A 1 = M 1 / h^2 for every
// coordinate (the stiffness rows sum to zero), and 0 without inertia.
TEST(CoordinatePreconditioner, ItsMatrixIsInertiaPlusAStiffnessThatTranslationsDoNotLoad)
{
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated })
  {
    Body body = cantilever(model, 1e6);
    body.pinned.clear();
    SceneSettings scene;
    scene.integrator = Integrator::ImplicitEuler;
    const MassSpringSetup prepared = prepareMassSpring(body, scene);
    const BodyElements elements{ prepared.model, &prepared.constants, &prepared.tetConstants };
    const CoordinateMatrix matrix(prepared.topology, elements, prepared.masses, prepared.mesh.points);
    const double h = 0.01;
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(matrix.rowCount()));
    const Eigen::VectorXd withInertia = matrix.assemble(h) * ones;
    const Eigen::VectorXd without = matrix.assemble(std::numeric_limits<double>::infinity(), false) * ones;
    double largestStiffness = 0.0;
    for (Eigen::Index r = 0; r < withInertia.size(); ++r)
    {
      const double mass = prepared.masses.mass[static_cast<std::size_t>(matrix.freeVertices()[static_cast<std::size_t>(r)])];
      EXPECT_NEAR(withInertia[r], mass / (h * h), 1e-9 * mass / (h * h)) << materialModelName(model);
      largestStiffness = std::max(largestStiffness, matrix.assemble(h).coeff(r, r));
    }
    EXPECT_LT(without.cwiseAbs().maxCoeff(), 1e-9 * largestStiffness) << materialModelName(model);
  }
}

// Steel at frame-rate steps is where block Jacobi needs many CG iterations per Newton step:
// the coordinate preconditioner reaches the same backward-Euler solution (to the solve's
// tolerance) in fewer of them, with one factorization (or hierarchy) for the whole run. (On a
// beam this slender the isotropic matrix overestimates bending's stiffness, so the cut is
// modest: about 1.6x for the network and 2.7x for the continuum models with the complete
// factor.)
TEST(CoordinatePreconditioner, SteelCantileverSameSolutionInFewerIterations)
{
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::Corotated,
         MaterialModel::StableNeoHookean })
  {
    const Body body = cantilever(model, 2e11);
    const SolveRun jacobi = run(body, Integrator::ImplicitEuler, LinearPreconditioner::BlockJacobi, 1.0 / 60, 6);
    for (LinearPreconditioner kind : wholeMeshKinds())
    {
      const SolveRun coordinate = run(body, Integrator::ImplicitEuler, kind, 1.0 / 60, 6);
      const std::string name = std::string(materialModelName(model)) + ", " + kindName(kind);
      EXPECT_EQ(coordinate.warnings, 0u) << name;
      EXPECT_EQ(coordinate.factorizations, 1) << name;
      // The sag here is ~1e-5 m: solutions agree far below it.
      EXPECT_LT(test::maxDistance(jacobi.positions, coordinate.positions), 1e-8) << name;
      EXPECT_LT(coordinate.cgPerNewton, 0.75 * jacobi.cgPerNewton)
        << name << ": " << coordinate.cgPerNewton << " against block Jacobi's " << jacobi.cgPerNewton;
      std::printf("%s: CG iterations per Newton iteration %.1f, block Jacobi %.1f\n", name.c_str(),
        coordinate.cgPerNewton, jacobi.cgPerNewton);
    }
  }
}

// The incomplete factor of the same matrix: the same solution, fewer CG iterations than block
// Jacobi (it sees A's couplings, not only each point's own block), more than the complete
// factor (which sees the whole mesh), and a factor no larger than A's lower triangle.
TEST(CoordinatePreconditioner, IncompleteFactorSameSolutionBetweenJacobiAndComplete)
{
  for (MaterialModel model : { MaterialModel::SpringNetwork, MaterialModel::StableNeoHookean })
  {
    const Body body = cantilever(model, 2e11);
    const SolveRun jacobi = run(body, Integrator::ImplicitEuler, LinearPreconditioner::BlockJacobi, 1.0 / 60, 6);
    const SolveRun complete = run(body, Integrator::ImplicitEuler, LinearPreconditioner::Coordinate, 1.0 / 60, 6);
    const SolveRun incomplete =
      run(body, Integrator::ImplicitEuler, LinearPreconditioner::IncompleteCoordinate, 1.0 / 60, 6);
    const std::string name = materialModelName(model);
    EXPECT_EQ(incomplete.warnings, 0u) << name;
    EXPECT_EQ(incomplete.factorizations, 1) << name;
    EXPECT_LT(test::maxDistance(jacobi.positions, incomplete.positions), 1e-8) << name;
    EXPECT_LT(incomplete.cgPerNewton, jacobi.cgPerNewton) << name;
    EXPECT_GE(incomplete.cgPerNewton, complete.cgPerNewton) << name;
    std::printf("%s: CG iterations per Newton iteration, block Jacobi %.1f, incomplete %.1f, complete %.1f\n",
      name.c_str(), jacobi.cgPerNewton, incomplete.cgPerNewton, complete.cgPerNewton);
  }
  SceneSettings scene;
  scene.integrator = Integrator::ImplicitEuler;
  scene.implicit.preconditioner = LinearPreconditioner::IncompleteCoordinate;
  MassSpringSimulation sim(cantilever(MaterialModel::Corotated, 1e6), scene);
  sim.advance(0.02);
  ASSERT_NE(sim.coordinatePreconditioner(), nullptr);
  EXPECT_EQ(sim.coordinatePreconditioner()->kind(), LinearPreconditioner::IncompleteCoordinate);
  const std::size_t points = sim.positions().size();
  // A's lower triangle over the free points: each row couples to at most its ~14 neighbours.
  EXPECT_GT(sim.coordinatePreconditioner()->factorBytes(), 0u);
  EXPECT_LT(sim.coordinatePreconditioner()->factorBytes(), points * 16 * (sizeof(double) + sizeof(int)));
}

// The static solve and BDF2 go through the same Newton solve: same answers with either
// preconditioner.
TEST(CoordinatePreconditioner, StaticSolveAndBdf2ReachTheSameSolution)
{
  const Body body = cantilever(MaterialModel::StableNeoHookean, 1e7);
  for (Integrator integrator : { Integrator::Static, Integrator::Bdf2 })
  {
    const SolveRun jacobi = run(body, integrator, LinearPreconditioner::BlockJacobi, 1.0 / 60, 4);
    for (LinearPreconditioner kind : wholeMeshKinds())
    {
      const SolveRun coordinate = run(body, integrator, kind, 1.0 / 60, 4);
      const std::string name = std::string(integratorName(integrator)) + ", " + kindName(kind);
      EXPECT_EQ(coordinate.warnings, 0u) << name;
      EXPECT_LT(test::maxDistance(jacobi.positions, coordinate.positions), 1e-7) << name;
      EXPECT_LT(coordinate.cgPerNewton, jacobi.cgPerNewton) << name;
    }
  }
}

// A step outside sqrt(2) of the factored one changes the matrix; steps within it reuse the
// factor.
TEST(CoordinatePreconditioner, RefactorsOnlyWhenTheStepLeavesSqrt2OfTheFactoredOne)
{
  const Body body = cantilever(MaterialModel::Corotated, 1e6);
  for (LinearPreconditioner kind : wholeMeshKinds())
  {
    SceneSettings scene;
    scene.integrator = Integrator::ImplicitEuler;
    scene.implicit.preconditioner = kind;
    scene.timeStep = 0.01;
    MassSpringSimulation sim(body, scene);
    sim.advance(0.05);
    ASSERT_NE(sim.coordinatePreconditioner(), nullptr) << kindName(kind);
    EXPECT_EQ(sim.coordinatePreconditioner()->factorizations(), 1) << kindName(kind);
    // A final partial step of 0.008 s (within sqrt 2) keeps the factor.
    sim.advance(0.058);
    EXPECT_EQ(sim.coordinatePreconditioner()->factorizations(), 1) << kindName(kind);
    // One of 0.003 s does not.
    sim.advance(0.061);
    EXPECT_EQ(sim.coordinatePreconditioner()->factorizations(), 2) << kindName(kind);
  }
}

TEST(CoordinatePreconditioner, ResultsDoNotDependOnTheThreadCount)
{
  std::vector<LinearPreconditioner> kinds = wholeMeshKinds();
  kinds.push_back(LinearPreconditioner::IncompleteCoordinate);
  for (LinearPreconditioner preconditioner : kinds)
  {
    std::vector<Vec3> positions[2];
    for (std::size_t threads : { 1u, 2u })
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      Body body;
      body.mesh = makeTetBox(6, 5, 4, 0.03, Vec3(0, 0, 0.05));
      body.material.model = MaterialModel::StableNeoHookean;
      SceneSettings scene;
      scene.integrator = Integrator::ImplicitEuler;
      scene.floorEnabled = true;
      scene.implicit.preconditioner = preconditioner;
      MassSpringSimulation sim(body, scene);
      for (int frame = 1; frame <= 12; ++frame)
      {
        sim.advance(frame / 30.0);
      }
      positions[threads - 1] = sim.positions();
    }
    EXPECT_EQ(positions[0], positions[1]) << kindName(preconditioner);
  }
}

// Where the build has hypre, the multigrid hierarchy holds A's own levels and interpolations:
// more than A, and a small multiple of it (aggressive coarsening keeps the coarse levels
// sparse). Where it has not, the setting is refused with the package to install.
TEST(CoordinatePreconditioner, AlgebraicMultigridWhereBuiltRefusedNamingThePackageWhereNot)
{
  SceneSettings scene;
  scene.integrator = Integrator::ImplicitEuler;
  scene.implicit.preconditioner = LinearPreconditioner::AlgebraicMultigrid;
  // Pinned at x = 0 so that it sags (a free fall is solved by its inertial prediction, with
  // no linear solve).
  Body body;
  body.mesh = makeTetBox(8, 8, 8, 0.02, Vec3(0, 0, 1));
  body.pinned.assign(body.mesh.points.size(), 0);
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    body.pinned[i] = body.mesh.points[i].x() < 1e-9 ? 1 : 0;
  }
  if (!algebraicMultigridAvailable())
  {
    try
    {
      MassSpringSimulation sim(body, scene);
      ADD_FAILURE() << "AlgebraicMultigrid was accepted by a build without hypre";
    }
    catch (const InvalidInputError& refusal)
    {
      EXPECT_NE(std::string(refusal.what()).find("libhypre-dev"), std::string::npos) << refusal.what();
    }
    return;
  }
  MassSpringSimulation sim(body, scene);
  sim.advance(0.02);
  ASSERT_NE(sim.coordinatePreconditioner(), nullptr);
  EXPECT_EQ(sim.coordinatePreconditioner()->kind(), LinearPreconditioner::AlgebraicMultigrid);
  EXPECT_TRUE(sim.warnings().empty());
  // A over the free points, both triangles: the diagonal and two entries per edge between
  // free points.
  const MassSpringSetup prepared = prepareMassSpring(body, scene);
  std::size_t points = 0, edges = 0;
  for (std::size_t i = 0; i < body.pinned.size(); ++i)
  {
    points += body.pinned[i] ? 0 : 1;
  }
  for (const auto& edge : prepared.topology.edges)
  {
    edges += body.pinned[static_cast<std::size_t>(edge.a)] || body.pinned[static_cast<std::size_t>(edge.b)] ? 0 : 1;
  }
  const std::size_t entries = points + 2 * edges;
  const std::size_t aBytes = entries * (sizeof(double) + sizeof(int)) + (points + 1) * sizeof(int);
  EXPECT_GT(sim.coordinatePreconditioner()->factorBytes(), aBytes);
  EXPECT_LT(sim.coordinatePreconditioner()->factorBytes(), 3 * aBytes);
  std::printf("hierarchy %.2f times A's bytes\n", double(sim.coordinatePreconditioner()->factorBytes()) / double(aBytes));
}

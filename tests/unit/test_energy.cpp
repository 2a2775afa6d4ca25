// Long undamped runs of a 3D body: 10^5 steps of each integrator against the body's own
// linearized modes. The stiffness matrix K comes from central differences of the internal
// forces at rest (zero velocity), the modes from M^-1/2 K M^-1/2, and each mode is then stepped
// by the integrator's textbook 2x2 recursion, written here independently of core. For a small
// displacement (strain ~4e-5) the body's energy E = kinetic + elastic after n steps must be the
// sum of the modes' energies: bounded for Verlet and Euler-Cromer, growing as the textbook says
// for Midpoint and Euler.
#include "softbody/massspring/mass_spring_forces.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"
#include "test_support.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace softbody;

namespace
{

Body undampedBox()
{
  Body body;
  body.mesh = makeTetBox(2, 2, 2, 0.05, Vec3(0, 0, 0.5)); // 27 points, 48 tets
  body.material.physical.dampingTime = 0.0;
  return body;
}

/// Squared angular frequencies and M^1/2-orthonormal mode shapes of the body at rest.
struct Modes
{
  Eigen::VectorXd omega2;
  Eigen::MatrixXd shapes; ///< columns phi_k; a displacement u has coordinates Phi^T M^1/2 u
};

Modes linearModes(const MassSpringSimulation& sim)
{
  const std::vector<Vec3>& rest = sim.restPositions();
  const std::size_t n = rest.size();
  const Eigen::Index dof = static_cast<Eigen::Index>(3 * n);
  std::vector<Vec3> x = rest, plus, minus;
  const std::vector<Vec3> v(n, Vec3::Zero());
  ForceScratch scratch;
  const double eps = 1e-8; // [m]; the forces are smooth: the O(eps^2) error is ~1e-14
  Eigen::MatrixXd k(dof, dof);
  for (Eigen::Index j = 0; j < dof; ++j)
  {
    Vec3& p = x[static_cast<std::size_t>(j / 3)];
    const double saved = p[j % 3];
    p[j % 3] = saved + eps;
    computeInternalForces(sim.topology(), sim.elementConstants(), x, v, scratch, plus);
    p[j % 3] = saved - eps;
    computeInternalForces(sim.topology(), sim.elementConstants(), x, v, scratch, minus);
    p[j % 3] = saved;
    for (Eigen::Index i = 0; i < dof; ++i)
    {
      const std::size_t a = static_cast<std::size_t>(i / 3);
      k(i, j) = -(plus[a][i % 3] - minus[a][i % 3]) / (2.0 * eps);
    }
  }
  Eigen::VectorXd invSqrtMass(dof);
  for (Eigen::Index i = 0; i < dof; ++i)
  {
    invSqrtMass[i] = 1.0 / std::sqrt(sim.masses()[static_cast<std::size_t>(i / 3)]);
  }
  const Eigen::MatrixXd scaled =
    invSqrtMass.asDiagonal() * (0.5 * (k + k.transpose())) * invSqrtMass.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(scaled);
  return { solver.eigenvalues().cwiseMax(0.0), solver.eigenvectors() };
}

/// One mode (x'' = -w2 x) stepped by the integrator's textbook recursion; energy (v^2 + w2 x^2)/2
/// with v as the integrator stores it (Verlet: the half-step velocity).
struct ModeState
{
  double x, v;
};

void stepMode(Integrator integrator, double h, double w2, ModeState& s, bool first)
{
  switch (integrator)
  {
    case Integrator::Euler:
      s = { s.x + h * s.v, s.v - h * w2 * s.x };
      break;
    case Integrator::Midpoint:
    {
      const double xm = s.x + 0.5 * h * s.v, vm = s.v - 0.5 * h * w2 * s.x;
      s = { s.x + h * vm, s.v - h * w2 * xm };
      break;
    }
    case Integrator::Verlet:
      s.v -= (first ? 0.5 * h : h) * w2 * s.x;
      s.x += h * s.v;
      break;
    case Integrator::EulerCromer:
      s.v -= h * w2 * s.x;
      s.x += h * s.v;
      break;
    case Integrator::ImplicitEuler:
    case Integrator::ProjectiveDynamics:
    case Integrator::Static:
    case Integrator::Bdf2:
    case Integrator::VertexBlockDescent:
      FAIL() << "explicit integrators only (test_implicit.cpp, test_bdf2.cpp and test_vertex_block_descent.cpp cover the implicit ones)";
  }
}

struct EnergyRun
{
  std::vector<double> body;      ///< E / E0 at each checkpoint
  std::vector<double> predicted; ///< the same from the modes
};

/// 10 checkpoints of `chunk` steps of h = `omegaH` / omega_max from a small random displacement.
EnergyRun runUndamped(Integrator integrator, double omegaH, int chunk)
{
  const Body body = undampedBox();
  MassSpringSimulation probe(body, SceneSettings{});
  const Modes modes = linearModes(probe);
  const double h = omegaH / std::sqrt(modes.omega2.maxCoeff());

  SceneSettings scene;
  scene.integrator = integrator;
  scene.gravity = Vec3::Zero();
  scene.timeStep = h;
  MassSpringSimulation sim(body, scene);
  DynamicState start = sim.state();
  start.positions = test::jitter(sim.restPositions(), 2e-6, 3); // 2e-6 m on 5 cm cells
  sim.restoreState(start);

  // Modal coordinates of the initial displacement (velocities 0).
  const Eigen::Index dof = modes.omega2.size();
  Eigen::VectorXd u(dof);
  for (Eigen::Index i = 0; i < dof; ++i)
  {
    const std::size_t a = static_cast<std::size_t>(i / 3);
    u[i] = std::sqrt(sim.masses()[a]) * (start.positions[a][i % 3] - sim.restPositions()[a][i % 3]);
  }
  const Eigen::VectorXd q = modes.shapes.transpose() * u;
  std::vector<ModeState> modeStates(static_cast<std::size_t>(dof));
  for (Eigen::Index k = 0; k < dof; ++k)
  {
    modeStates[static_cast<std::size_t>(k)] = { q[k], 0.0 };
  }
  auto modalEnergy = [&] {
    double e = 0.0;
    for (Eigen::Index k = 0; k < dof; ++k)
    {
      const ModeState& s = modeStates[static_cast<std::size_t>(k)];
      e += 0.5 * (s.v * s.v + modes.omega2[k] * s.x * s.x);
    }
    return e;
  };

  const double body0 = sim.mechanicalEnergy(), modal0 = modalEnergy();
  EXPECT_NEAR(body0 / modal0, 1.0, 1e-3); // the linearization holds at this amplitude
  EnergyRun run;
  long long done = 0;
  for (int checkpoint = 1; checkpoint <= 10; ++checkpoint)
  {
    sim.advance(double(checkpoint) * chunk * h);
    for (int s = 0; s < chunk; ++s, ++done)
    {
      for (Eigen::Index k = 0; k < dof; ++k)
      {
        stepMode(integrator, h, modes.omega2[k], modeStates[static_cast<std::size_t>(k)], done == 0);
      }
    }
    EXPECT_EQ(sim.stepCount(), static_cast<unsigned long long>(done));
    run.body.push_back(sim.mechanicalEnergy() / body0);
    run.predicted.push_back(modalEnergy() / modal0);
  }
  return run;
}

void expectFollowsTheModes(const EnergyRun& run, double tolerance, const char* name)
{
  for (std::size_t c = 0; c < run.body.size(); ++c)
  {
    EXPECT_NEAR(run.body[c] / run.predicted[c], 1.0, tolerance)
      << name << " checkpoint " << c + 1 << ": E/E0 " << run.body[c] << ", modes say "
      << run.predicted[c];
  }
  std::printf("%s: E/E0 after 10 checkpoints %.6f (modes %.6f)\n", name, run.body.back(),
    run.predicted.back());
}

} // namespace

TEST(UndampedEnergy, SymplecticMethodsStayBoundedOverAHundredThousandSteps)
{
  // omega_max h = 1: half the symplectic limit. No secular drift: at every checkpoint the energy
  // is what the modes predict. E itself oscillates (the modified energy is the conserved one;
  // at omega h = 1 the top modes' E swings by up to +-50%): measured between 0.909 and 1.207.
  for (Integrator integrator : { Integrator::Verlet, Integrator::EulerCromer })
  {
    const EnergyRun run = runUndamped(integrator, 1.0, 10000);
    expectFollowsTheModes(run, 1e-3, integratorName(integrator));
    for (double e : run.body)
    {
      EXPECT_NEAR(e, 1.0, 0.3) << integratorName(integrator);
    }
  }
}

TEST(UndampedEnergy, MidpointAndEulerDriftAsTheirAmplificationSays)
{
  // Both gain energy every step on an undamped body (no stable step exists without damping):
  // Midpoint by (1 + (w h)^4 / 4) per step and mode, Euler by (1 + (w h)^2). With omega_max h
  // = 0.1 (Midpoint) and 0.005 (Euler) over 10^5 steps the body's energy grows by the factors
  // the modes predict (measured: see the printed lines), monotonically.
  const EnergyRun midpoint = runUndamped(Integrator::Midpoint, 0.1, 10000);
  expectFollowsTheModes(midpoint, 1e-3, "Midpoint");
  const EnergyRun euler = runUndamped(Integrator::Euler, 0.005, 10000);
  expectFollowsTheModes(euler, 1e-3, "Euler");
  for (const EnergyRun* run : { &midpoint, &euler })
  {
    EXPECT_GT(run->body.back(), 1.05);
    for (std::size_t c = 1; c < run->body.size(); ++c)
    {
      EXPECT_GT(run->body[c], run->body[c - 1]);
    }
  }
}

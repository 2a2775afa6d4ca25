// Vertex Block Descent (Chen, Macklin, Yang, Kavan 2024, "Vertex Block Descent", SIGGRAPH):
// backward Euler solved by block coordinate descent on the incremental potential
// (incremental_potential.h), one point at a time. A sweep visits the points color by color
// (mesh/graph_coloring.h: points joined by an edge differ in color) and moves each by one 3 x 3
// Newton step on Phi as a function of that point alone,
//
//   x_i <- x_i - H_ii^-1 g_i,   g_i = dPhi/dx_i,   H_ii = m_i / h^2 I + sum_e (H_e)_ii
//
// with its elements evaluated where their other corners are now (the earlier colors already
// moved): Gauss-Seidel, so a sweep carries a change across the mesh in one pass. The points of
// one color share no element, so they are updated in parallel, each writing only itself: the
// result does not depend on the thread count. (H_e)_ii is the diagonal block of the element's
// PSD-projected Hessian, the same the Newton solves use, so H_ii is positive definite wherever
// there is inertia.
//
// Each sweep is one iteration of the shared implicit solve (implicit_solve.h): its direction
// is the sweep's whole displacement, filtered per point as the solve asks (held points do not
// move, points on their contact plane move along it, conditions' held components stay), and
// the solve's line search, floor and obstacle active set, friction and convergence test apply
// as they do to Newton and Projective Dynamics. ImplicitTolerance 0 runs ImplicitMaxIterations
// sweeps per step, as the paper's fixed iteration counts do; a tolerance stops at the residual.
//
// Chebyshev acceleration (Wang 2015, as the paper uses it): each iterate is pushed past the
// sweep, x+ = omega (sweep - x_prev) + x_prev, with omega from the assumed spectral radius rho
// (ImplicitSettings::chebyshevRadius; omega_1 = 1, omega_2 = 2 / (2 - rho^2), omega_k+1 =
// 4 / (4 - rho^2 omega_k)), and the result filtered per point like the sweep. It is not monotone
// in Phi: the solve's line search takes what lowers it. Not built: the paper's own collision
// handling (contacts are the solve's active set).
#pragma once

#include "softbody/massspring/implicit_integrator.h"
#include "softbody/massspring/implicit_solve.h"
#include "softbody/mesh/graph_coloring.h"

#include <memory>

namespace softbody
{

class VertexBlockDescentStepper final : public ImplicitIntegrator
{
public:
  VertexBlockDescentStepper(const Topology& topology, const BodyElements& elements, const PointMasses& masses,
    const SceneSettings& scene);

  /// One step of h; the sweeps are timed as Stage::Forces (they are element passes).
  void step(double h, DynamicState& state, StepPlan& plan) override;

  const ImplicitConvergence& convergence() const override { return Convergence; }
  IncrementalPotential& potential() override { return *Potential; }
  ContactPlanes& contactPlanes() override { return Solver.contactPlanes(); }
  std::size_t colorCount() const { return Colors.colorCount(); }

private:
  /// One sweep from at.x into `direction` (the displacement).
  void sweep(const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction);

  std::unique_ptr<IncrementalPotential> Potential;
  ImplicitStepSolver Solver;
  Coloring Colors;
  /// Chebyshev acceleration of a sweep from at.x (direction: the sweep's displacement, made
  /// the accelerated one).
  void accelerate(const ImplicitStepSolver::Iterate& at, std::vector<Vec3>& direction);

  double Rho = 0.0; ///< Chebyshev's assumed spectral radius (0: plain sweeps)
  std::vector<Vec3> Y; ///< the sweep's positions
  // Chebyshev's state within a step: the iterate before at.x, at.x itself (a direction asked
  // for again at the same x, after points were held, reuses them) and omega.
  std::vector<Vec3> Previous, Current;
  double Omega = 1.0;
  ImplicitConvergence Convergence;
};

} // namespace softbody

// What a mass-spring simulation is built from besides its body (scene/body.h): the scene
// settings (integrator, step, gravity, floor, strain limit). Immutable once the stepper is made.
#pragma once

#include "softbody/common/sparse_cholesky.h"
#include "softbody/integrators/explicit_integrators.h"
#include "softbody/material/material.h"
#include "softbody/mesh/tet_mesh.h"
#include "softbody/scene/body.h"
#include "softbody/scene/conditions.h"
#include "softbody/scene/scene.h"

#include <vector>

namespace softbody
{

/// What preconditions the conjugate gradients of Implicit Euler's, BDF2's and the static
/// solve's Newton iterations (block_pcg.h, coordinate_preconditioner.h).
enum class LinearPreconditioner
{
  BlockJacobi, ///< each point's own 3x3 block: no set-up, many iterations on large meshes
  Coordinate,  ///< a sparse Cholesky factor of the isotropic step matrix, reused across steps
  /// The same matrix's incomplete Cholesky factor (Eigen, no fill beyond A's pattern): a
  /// factor the size of A and quick to make, that sees less of the long-range coupling
  IncompleteCoordinate,
  /// One V-cycle of an algebraic multigrid hierarchy of the same matrix (hypre's BoomerAMG,
  /// amg_preconditioner.h): linear work per application, where the complete factor's solve
  /// grows faster than the mesh. Only in builds with hypre (libhypre-dev)
  AlgebraicMultigrid
};

/// How the implicit integrators solve each step (see implicit_euler.h, projective_dynamics.h).
struct ImplicitSettings
{
  /// The step's equations hold when the mass-weighted RMS residual acceleration is below
  /// tolerance times the reference (gravity, or the step's initial residual if larger).
  /// Projective Dynamics: 0 = always run maxIterations local/global iterations.
  double tolerance = 1.0e-3;
  /// Newton iterations (Implicit Euler) or local/global iterations (Projective Dynamics).
  int maxIterations = 100;
  /// Projective Dynamics: (s, y) pairs of the L-BFGS acceleration (Liu et al. 2017), which
  /// uses the prefactored matrix as its initial Hessian; 0 = plain local/global iterations.
  int projectiveHistory = 10;
  /// Vertex Block Descent: the spectral radius rho its Chebyshev acceleration assumes (Wang
  /// 2015; Chen et al. 2024 use it over their sweeps), in [0, 1); 0 = plain sweeps.
  double chebyshevRadius = 0.95;
  LinearPreconditioner preconditioner = LinearPreconditioner::BlockJacobi;
  /// The factorization of Projective Dynamics' matrix and of the coordinate preconditioner.
  CholeskyBackend cholesky = CholeskyBackend::CholmodSupernodal;
  bool operator==(const ImplicitSettings&) const = default;
};

/// The mass-spring method's settings on top of the scene every method shares.
struct SceneSettings : Scene
{
  Integrator integrator = Integrator::EulerCromer;
  /// [s]; 0 = automatic: explicit integrators take the largest stable step estimate times
  /// stabilitySafety; implicit ones one step per advance() call (the filter: one per frame).
  /// With error-controlled steps (Scene::stepControl), > 0 is the largest step the
  /// controller may take.
  double timeStep = 0.0;
  double stabilitySafety = 0.9; ///< fraction of the estimated stable step used in auto mode
  /// Strain limit: maximum l / l0 of a spring (> 1); 0 disables strain limiting.
  double strainLimit = 0.0;
  int strainLimitIterations = 4;
  InvertedTetPolicy invertedTets = InvertedTetPolicy::Reorient;
  /// A state is declared exploded when a spring grows past this factor of its rest length.
  double divergenceStretch = 100.0;
  ImplicitSettings implicit;
  bool operator==(const SceneSettings&) const = default;
};

} // namespace softbody

// Algebraic multigrid as the coordinate preconditioner's approximate inverse of A
// (LinearPreconditioner::AlgebraicMultigrid): one BoomerAMG hierarchy (hypre, Henson and Yang
// 2002) of the scalar step matrix, applied as one V-cycle from a zero guess to each of x, y
// and z. A V-cycle with a forward Gauss-Seidel sweep going down, the backward one coming up
// and an exact coarsest solve is a symmetric positive definite operator, so conjugate
// gradients stay conjugate gradients.
//
// hypre is optional (Debian libhypre-dev); a build without it has no AlgebraicMultigrid, and
// the set-up refuses the setting (mass_spring_setup.cpp).
#pragma once

#include "softbody/massspring/coordinate_solver.h"

#include <memory>

namespace softbody
{

/// Whether this build has hypre.
bool algebraicMultigridAvailable();
/// Throws InvalidInputError, naming the package to install, where the build has no hypre.
void requireAlgebraicMultigrid();

/// The BoomerAMG solver (requireAlgebraicMultigrid() first).
std::unique_ptr<CoordinateSolver> makeAlgebraicMultigrid();

} // namespace softbody

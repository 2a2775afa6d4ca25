// The backward-Euler step of the mass-spring model as a minimization (Martin et al. 2011,
// "Example-based elastic materials"; Gast et al. 2015): one step of h from (x0, v0) is the
// minimizer x of the incremental potential
//
//   Phi(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 - m_i g . x_i        inertia and gravity
//          + sum_e k_e / 2 (l_e - l0_e)^2 + sum_t K_t / 2 (V_t - V0_t)^2     elastic energy
//          + sum_e kd_e / (2h) (n0_e . (dx_a - dx_b))^2                 spring damping
//          + sum_t Kd_t / (2h) (sum_c g0_c . dx_c)^2                    volume damping
//
// with y = x0 + h v0, dx = x - x0, and v = dx / h afterwards. Its gradient is zero exactly when
// M (v - v0) / h = f_elastic(x) + f_damping + M g, the backward-Euler equations. The damping
// directions n0 (spring axes) and g0 (volume gradients) are those of the step's start: the
// damping force is then linear in x, -D0 (x - x0) / h, as in the explicit model's
// f = -k_d n (n . v_ab), so Phi is a true potential and a line search on it is sound.
//
// The Hessian used by Newton's method is made positive semi-definite per element:
//   springs: k [n n^T + max(0, 1 - l0/l) (I - n n^T)], the exact Hessian with its negative
//            transverse eigenvalue (a compressed spring) clamped to zero (Choi and Ko 2002);
//   volumes: K g g^T, the Gauss-Newton part; the dropped curvature K (V - V0) d2V/dx2 is
//            indefinite whenever V != V0, and projecting it exactly needs a 12x12 eigen
//            decomposition per tet and step. Their damping enters as (Kd / h) g g^T (see
//            assembleHessian).
// Pinned points (inverse mass 0) are fixed: their rows are inactive.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/massspring/block_sparse_matrix.h"
#include "softbody/material/mass.h"

#include <vector>

namespace softbody
{

class IncrementalPotential
{
public:
  IncrementalPotential(const Topology& topology, const ElementConstants& constants,
    const PointMasses& masses, const Vec3& gravity);

  /// Starts a step of h from (x0, v0): the inertial target y and the frozen damping directions.
  void beginStep(const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, double h);

  /// A starting point: the inertial target y = x0 + h v0, plus h^2 g when `withGravity` (the
  /// explicit prediction, exact in free fall); x0 for fixed points.
  void predict(std::vector<Vec3>& x, bool withGravity) const;

  /// Phi(x) [J]; also fills the gradient [N] (zero on fixed points) and keeps the tet data
  /// that assembleHessian() reuses.
  double evaluate(const std::vector<Vec3>& x, std::vector<Vec3>& gradient);

  /// The PSD-projected Hessian at x, which must be the x of the last evaluate(); fixed rows get
  /// the identity. (Only Newton needs it, and only at accepted iterates: evaluate() skips it.)
  void assembleHessian(const std::vector<Vec3>& x, BlockSparseMatrix& hessian);

  /// Mass-weighted RMS of the residual acceleration, sqrt(sum_i |G_i|^2 / m_i / sum_i m_i)
  /// [m/s^2]: how far the step's equations are from holding, in the units of g.
  double residualAcceleration(const std::vector<Vec3>& gradient) const;

  /// The acceleration scale the residual is measured against [m/s^2]: the larger of |g| and
  /// the RMS speed at the step's start over h (a body thrown without gravity), never 0.
  double referenceAcceleration(double gravityNorm) const;

  const std::vector<char>& active() const { return Active; }
  double inverseMass(std::size_t i) const { return InverseMass[i]; }
  std::size_t vertexCount() const { return Topo.vertexCount; }
  double step() const { return H; }

private:
  void elementPass(const std::vector<Vec3>& x);
  void springHessianPass(const std::vector<Vec3>& x);
  void findCornerSlots(const BlockSparseMatrix& hessian);

  const Topology& Topo;
  const ElementConstants& Constants;
  const std::vector<double>& InverseMass;
  Vec3 Gravity;
  std::vector<char> Active; ///< free points (inverse mass > 0)
  double ActiveMass = 0.0;

  // Per step
  double H = 0.0;
  double SpeedScale = 0.0; ///< mass-weighted RMS speed at the step's start [m/s]
  std::vector<Vec3> X0, Target;          ///< x0 and y
  std::vector<Vec3> DampingAxis;         ///< n0 per edge
  std::vector<std::array<Vec3, 4>> DampingGradient; ///< g0 per tet

  // Per evaluate(): element data at x
  std::vector<Vec3> SpringGradient;   ///< dPhi/dx_a of each edge (x_b gets its negative)
  std::vector<Mat3> SpringHessian;    ///< its PSD block (elastic + damping); assembleHessian()
  std::vector<std::array<Vec3, 4>> TetGradient; ///< dV/dx_c at x
  std::vector<double> TetScale;       ///< K (V - V0): the volume gradient's factor
  std::vector<double> TetDampingScale; ///< Kd / h (g0 . dx): the damping gradient's factor
  std::vector<double> ElementEnergy;  ///< per edge then per tet, summed in a fixed order
  std::vector<std::array<std::int32_t, 3>> CornerSlots; ///< per tet corner: its 3 edge blocks
};

} // namespace softbody

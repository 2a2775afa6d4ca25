// Finite elements on linear tets for the continuum models (isotropic_elasticity.h): each tet has
// a constant deformation gradient
//   F = sum_c x_c g_c^T,   g_c = dF/dx_c [1/m] (rest shape gradients; g_0 = -(g_1 + g_2 + g_3)),
// elastic energy V0 Psi(F), corner forces -V0 P(F) g_c, and a Hessian block for corners a, b of
//   H_ab[alpha][beta] = V0 sum_jl dP/dF(3 alpha + j, 3 beta + l) g_a[j] g_b[l].
//
// Damping is Kelvin-Voigt viscosity with the material's damping time beta: the second
// Piola-Kirchhoff viscous stress beta C : D, C the linear elasticity tensor of the typed E and
// nu and D the Green strain rate sym(F^T dF/dt), so P_visc = F beta C : D. For small motions
// about rest it is the stiffness-proportional Rayleigh damping beta K v the spring network has,
// and it leaves rigid rotations undamped (F^T dF/dt is skew for them). It needs no polar
// decomposition. In the incremental potential (as in spring_network.h) the frame is F0, the
// one at the step's start, and dF/dt = (F - F0) / h, so the damping term is the quadratic
//   V0 h / 2 beta (2 mu |D|^2 + lambda tr(D)^2),   D = sym(F0^T (F - F0)) / h,
// with its exact (constant, positive semi-definite) Hessian (beta / h) C seen from F0.
// The elastic Hessian is projected exactly from its closed-form eigensystem.
#pragma once

#include "softbody/material/elastic_laws.h"
#include "softbody/material/element_model.h"
#include "softbody/material/isotropic_elasticity.h"
#include "softbody/material/material.h"
#include "softbody/material/nodal_pressure.h"
#include "softbody/material/tet_corners.h"
#include "softbody/mesh/topology.h"

#include <array>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace softbody
{

/// Per-tet constants of a continuum body.
struct TetElasticConstants
{
  MaterialModel model = MaterialModel::Corotated;
  std::vector<std::array<Vec3, 4>> shapeGradients; ///< g_c [1/m]
  std::vector<double> restVolume;                  ///< V0 [m^3] (positive)
  std::vector<LameParameters> linear;              ///< mu, lambda of the typed E and nu [Pa]
  std::vector<LameParameters> law;                 ///< the law's own parameters [Pa]
  std::vector<double> dampingTime;                 ///< beta [s]
  bool damped = true; ///< false: the static solve's potential (no viscosity)
  /// VolumetricFormulation::NodalAverage: the volumetric term at the points (nodal_pressure.h).
  bool nodalPressure = false;
  NodalPressureConstants nodal; ///< filled when nodalPressure
};

/// The constants of `material` (whose model must be a continuum one) on positively oriented
/// tets; validates the material like computeElementConstants.
TetElasticConstants computeTetElasticConstants(const Topology& topology,
  const std::vector<Vec3>& restPositions, const MaterialSettings& material,
  std::vector<std::string>& warnings);

/// F = sum_c x_c g_c^T of tet t.
inline Mat3 deformationGradient(const Topology& topology, const TetElasticConstants& c,
  std::size_t t, const std::vector<Vec3>& x)
{
  const Tet& tet = topology.tets[t];
  const std::array<Vec3, 4>& g = c.shapeGradients[t];
  Mat3 f = x[tet[0]] * g[0].transpose();
  for (int k = 1; k < 4; ++k)
  {
    f.noalias() += x[tet[k]] * g[static_cast<std::size_t>(k)].transpose();
  }
  return f;
}

/// The viscous stress beta G (2 mu D + lambda tr(D) I), D = sym(G^T rate), seen from the frame
/// G (the current F for the explicit integrators, F0 in the incremental potential) [Pa].
inline Mat3 viscousStress(const Mat3& frame, const Mat3& rate, const LameParameters& p,
  double beta)
{
  const Mat3 local = frame.transpose() * rate;
  const Mat3 d = 0.5 * (local + local.transpose());
  return beta * frame * (2.0 * p.mu * d + p.lambda * d.trace() * Mat3::Identity());
}

/// Psi [Pa] and P of a tet under the nodal-averaged pressure (nodal_pressure.h): the law's,
/// without its volumetric term lambda / 2 (J - 1)^2 (whose energy the points hold), and with
/// `pressure`, the tet's share of the points' pressure, in place of its own lambda (J - 1).
template <IsotropicLaw Law>
double energyAndStressWithPressure(const Mat3& f, const LameParameters& p, double pressure, Mat3& stress)
{
  double energy = energyAndStress<Law>(f, p, stress);
  const Mat3 cofactor = cofactorOf(f);
  const double excess = f.col(0).dot(cofactor.col(0)) - 1.0; // J - 1
  stress += (pressure - p.lambda * excess) * cofactor;
  return energy - 0.5 * p.lambda * excess * excess;
}

/// Psi [Pa] and P of tet t at F: its law's, or with the nodal pressure where the constants ask
/// for it (`field` then evaluated at the same positions).
template <IsotropicLaw Law>
double tetEnergyAndStress(const TetElasticConstants& c, std::size_t t, const Mat3& f,
  const NodalPressureField* field, Mat3& stress)
{
  return c.nodalPressure ? energyAndStressWithPressure<Law>(f, c.law[t], field->tetPressure[t], stress)
                         : energyAndStress<Law>(f, c.law[t], stress);
}

/// The tets of a continuum body under `Law` as an element family (element_model.h).
template <IsotropicLaw Law>
class TetElasticFamily
{
public:
  static constexpr int kCorners = 4;
  /// Unprojected, dP/dF from the analytic eigensystem is the law's exact derivative.
  static constexpr bool kExactHessian = true;
  struct StepData
  {
    Mat3 f0; ///< F at the step's start: the viscous frame
  };
  struct AtX
  {
    std::array<Vec3, 4> gradient; ///< dE/dx_c [N]
  };
  /// The blocks H_ab for a <= b, in the order (0,0) (0,1) (0,2) (0,3) (1,1) (1,2) ... (3,3).
  using HessianData = std::array<Mat3, 10>;

  /// `field`: the nodal pressure at the positions of the next evaluate() (constants with
  /// nodalPressure only; see TetElasticModel).
  TetElasticFamily(const Topology& topology, const TetElasticConstants& constants,
    const NodalPressureField* field = nullptr)
    : Topo(&topology)
    , Constants(&constants)
    , Field(field)
  {
  }

  std::size_t size() const { return Topo->tets.size(); }
  std::array<std::int32_t, 4> corners(std::size_t t) const { return Topo->tets[t]; }
  std::int32_t edgeBetween(std::size_t t, int a, int b) const
  {
    return tetEdgeBetween(*Topo, t, a, b);
  }
  template <class Visit>
  void forEachCorner(std::int32_t vertex, Visit&& visit) const
  {
    forEachTetCorner(*Topo, vertex, visit);
  }

  StepData stepData(std::size_t t, const std::vector<Vec3>& x0) const
  {
    return { deformationGradient(*Topo, *Constants, t, x0) };
  }

  double evaluate(std::size_t t, const std::vector<Vec3>& x, const StepStart& start,
    const StepData& step, AtX& out) const
  {
    const TetElasticConstants& c = *Constants;
    const Mat3 f = deformationGradient(*Topo, c, t, x);
    Mat3 stress;
    double energy = tetEnergyAndStress<Law>(c, t, f, Field, stress);
    if (c.damped && c.dampingTime[t] > 0.0)
    {
      const Mat3 rate = (f - step.f0) / start.h;
      const Mat3 viscous = viscousStress(step.f0, rate, c.linear[t], c.dampingTime[t]);
      stress += viscous;
      // h / 2 beta (2 mu |D|^2 + lambda tr(D)^2) = h / 2 viscous : rate: the viscous stress is
      // F0 times a symmetric tensor T, and T : sym(F0^T rate) = (F0 T) : rate.
      energy += 0.5 * start.h * (viscous.cwiseProduct(rate)).sum();
    }
    const double v0 = c.restVolume[t];
    for (std::size_t k = 0; k < 4; ++k)
    {
      out.gradient[k] = v0 * stress * c.shapeGradients[t][k];
    }
    return v0 * energy;
  }

  Vec3 cornerGradient(const StepData&, const AtX& at, int corner) const
  {
    return at.gradient[static_cast<std::size_t>(corner)];
  }

  HessianData hessianData(std::size_t t, const std::vector<Vec3>& x, const StepStart& start,
    const StepData& step, const AtX&) const
  {
    const TetElasticConstants& c = *Constants;
    const RotationVariantSvd svd = rotationVariantSvd(deformationGradient(*Topo, c, t, x));
    Mat9 dpdf = c.nodalPressure
      ? stressDerivativeWithPressure<Law>(svd, c.law[t], Field->tetPressure[t], !start.exactHessian)
      : stressDerivative<Law>(svd, c.law[t], !start.exactHessian);
    if (c.damped && c.dampingTime[t] > 0.0)
    {
      dpdf += (c.dampingTime[t] / start.h) * viscousTensor(step.f0, c.linear[t]);
    }
    return blocksOf(dpdf, c.shapeGradients[t], c.restVolume[t]);
  }

  Mat3 hessianBlock(const StepData&, const AtX&, const HessianData& h, int a, int b) const
  {
    return a <= b ? h[blockIndex(a, b)] : Mat3(h[blockIndex(b, a)].transpose());
  }

  /// Row-norm bound at rest: the rest Hessian is V0 B^T C B, and |C| = max(2 mu, 2 mu + 3 lambda)
  /// (its deviatoric and volumetric eigenvalues), so sum_b |H_ab| <= V0 |C| |g_a| sum_b |g_b|.
  double stiffnessBound(std::size_t t, int a, const std::vector<Vec3>&) const
  {
    const TetElasticConstants& c = *Constants;
    const std::array<Vec3, 4>& g = c.shapeGradients[t];
    const LameParameters& p = c.linear[t];
    const double modulus = std::max(2.0 * p.mu, 2.0 * p.mu + 3.0 * p.lambda);
    const double sum = g[0].norm() + g[1].norm() + g[2].norm() + g[3].norm();
    return c.restVolume[t] * modulus * g[static_cast<std::size_t>(a)].norm() * sum;
  }

  /// The ten blocks V0 G_a^T dP/dF G_b (a <= b) of a 9x9 stress derivative.
  static HessianData blocksOf(const Mat9& dpdf, const std::array<Vec3, 4>& g, double v0)
  {
    // W_b = dP/dF (e_beta g_b^T) for each beta: a 9x3 matrix per corner.
    std::array<Eigen::Matrix<double, 9, 3>, 4> w;
    for (std::size_t b = 0; b < 4; ++b)
    {
      for (int beta = 0; beta < 3; ++beta)
      {
        w[b].col(beta) = dpdf.middleCols<3>(3 * beta) * g[b];
      }
    }
    HessianData blocks;
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a; b < 4; ++b)
      {
        Mat3& block = blocks[blockIndex(a, b)];
        for (int alpha = 0; alpha < 3; ++alpha)
        {
          block.row(alpha) = v0 * g[static_cast<std::size_t>(a)].transpose() *
            w[static_cast<std::size_t>(b)].middleRows<3>(3 * alpha);
        }
      }
    }
    return blocks;
  }

private:
  static constexpr std::size_t blockIndex(int a, int b)
  {
    constexpr int kRowStart[4] = { 0, 4, 7, 9 };
    return static_cast<std::size_t>(kRowStart[a] + (b - a));
  }

  const Topology* Topo;
  const TetElasticConstants* Constants;
  const NodalPressureField* Field;
};

/// A continuum body as a material model: one family, its tets; with the nodal pressure, also
/// the points' volumetric term, which ModelPotential asks for through beginEvaluate (before
/// the element pass), globalEnergy and addCoupling.
template <IsotropicLaw Law>
class TetElasticModel
{
public:
  TetElasticModel(const Topology& topology, const TetElasticConstants& constants)
    : Topo(&topology)
    , Constants(&constants)
    , Field(std::make_unique<NodalPressureField>())
    , Tets(topology, constants, Field.get())
  {
  }
  std::tuple<const TetElasticFamily<Law>&> families() const { return { Tets }; }

  void beginEvaluate(const std::vector<Vec3>& x)
  {
    if (Constants->nodalPressure)
    {
      evaluateNodalPressure(*Topo, *Constants, x, *Field);
    }
  }
  double globalEnergy() const { return Constants->nodalPressure ? Field->energy : 0.0; }
  void addCoupling(const std::vector<Vec3>& x, const std::vector<char>& active, BlockSparseMatrix& hessian) const
  {
    if (Constants->nodalPressure)
    {
      addNodalPressureCoupling(*Topo, *Constants, x, active, hessian);
    }
  }

private:
  const Topology* Topo;
  const TetElasticConstants* Constants;
  std::unique_ptr<NodalPressureField> Field; // owned apart, so the family's pointer survives a move
  TetElasticFamily<Law> Tets;
};

static_assert(ElementFamily<TetElasticFamily<CorotatedLaw>>);
static_assert(ElementModel<TetElasticModel<StableNeoHookeanLaw>>);

} // namespace softbody

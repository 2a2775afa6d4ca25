// The material seam: what an element family must provide so that the implicit solvers (the
// incremental potential of incremental_potential.h, and through it Implicit Euler and
// Projective Dynamics) can use it without knowing its constitutive law.
//
// An element family is a set of elements of the same kind (springs, tets) with a fixed number
// of corners each (2 for a spring, 4 for a tet). It is a small value type over constants and
// connectivity it does not own; every operation is per element, pure (no state written), and
// resolved at compile time: the solvers are templated on the family, so there is no virtual
// call per element (the shape of HOBAK's energies, Kim and Eberle 2020, with templates in place
// of its virtual functions).
//
// Per element e at positions x [m] the family gives
//   evaluate        its energy [J], and fills the element's data at x (`AtX`)
//   cornerGradient  dE/dx_a [N] of corner a, from that data
//   hessianData,    the blocks d2E/dx_a dx_b [N/m] of a positive semi-definite approximation of
//   hessianBlock    its Hessian (corner a, corner b; symmetric, H_ba = H_ab^T). How each family
//                   projects its Hessian is written beside it (see incremental_potential.h's
//                   header for the spring network's). A family whose Hessian is exact without
//                   the projection says so with `static constexpr bool kExactHessian = true`
//                   and gives it when StepStart::exactHessian asks (Newton near its solution,
//                   where the projection's clamping would cost its quadratic convergence)
//   stiffnessBound  an upper bound, at rest, on sum_b |H_ab| (spectral norms) for corner a
//                   [N/m]: the element's share of a Gershgorin bound on the stiffest mode, which
//                   limits the stable step of the explicit integrators
// and the connectivity the assembly needs: its corners' point indices, for each point the
// (element, corner) pairs it is a corner of, in a fixed order (the gather order, which fixes
// the summation order and so the result at any thread count), and for two corners the mesh
// edge joining them (the block of the Hessian's pattern they write).
//
// Damping is part of the family, not a family of its own. The network's Rayleigh damping is
// stiffness-proportional per element (k_d = beta k), and in the incremental potential it acts
// along directions frozen at the step's start (spring axes, volume gradients at x0), so that
// the damping force is linear in x and Phi stays a potential. Those directions are the family's
// per-step data (`StepData`, made once per step by `stepData` from x0), and evaluate() returns
// the element's elastic and damping energy together: the two share the element's constants and
// are summed per element, in one expression, exactly as the potential always summed them. A
// separate damping family would add its energies as separate terms and change the order of the
// sums (and so the last bits of every result). A family without damping returns its
// elastic terms only and an empty StepData.
#pragma once

#include "softbody/common/geometry.h"

#include <Eigen/Core>

#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace softbody
{

using Mat3 = Eigen::Matrix3d;

/// What an element needs of the step besides the current positions: its start x0 [m] and
/// length h [s] (a damping rate is (x - x0) / h along the frozen directions).
struct StepStart
{
  const std::vector<Vec3>& x0;
  double h;
  /// hessianData: the element's exact Hessian, which may be indefinite, instead of its PSD
  /// projection (only asked of families with kExactHessian).
  bool exactHessian = false;
};

/// Whether family F gives its exact Hessian when asked (see the header comment).
template <class F>
constexpr bool hasExactHessian()
{
  if constexpr (requires { F::kExactHessian; })
  {
    return F::kExactHessian;
  }
  else
  {
    return false;
  }
}

/// The operations of one element family (see the header comment for their meaning and units).
template <class F>
concept ElementFamily = requires(const F& family, std::size_t e, int a,
  const std::vector<Vec3>& x, const StepStart& start, const typename F::StepData& stepData,
  typename F::AtX& atX, const typename F::HessianData& hessianData, std::int32_t vertex) {
  requires std::same_as<decltype(F::kCorners), const int>;
  requires F::kCorners >= 2;
  { family.size() } -> std::convertible_to<std::size_t>;
  { family.corners(e) } -> std::same_as<std::array<std::int32_t, F::kCorners>>;
  { family.edgeBetween(e, a, a) } -> std::convertible_to<std::int32_t>;
  { family.forEachCorner(vertex, [](std::size_t, int) {}) };
  { family.stepData(e, x) } -> std::same_as<typename F::StepData>;
  { family.evaluate(e, x, start, stepData, atX) } -> std::same_as<double>;
  { family.cornerGradient(stepData, std::as_const(atX), a) } -> std::same_as<Vec3>;
  { family.hessianData(e, x, start, stepData, std::as_const(atX)) }
    -> std::same_as<typename F::HessianData>;
  { family.hessianBlock(stepData, std::as_const(atX), hessianData, a, a) }
    -> std::same_as<Mat3>;
  { family.stiffnessBound(e, a, x) } -> std::convertible_to<double>;
};

/// A material model for the implicit solvers: a type whose `families()` returns a std::tuple of
/// references to its element families (each an ElementFamily), in the order their energies are
/// summed and their contributions gathered at each point.
namespace detail
{
template <class T>
struct AreElementFamilies : std::false_type
{
};
template <class... F>
struct AreElementFamilies<std::tuple<F...>>
  : std::bool_constant<(ElementFamily<std::remove_cvref_t<F>> && ...)>
{
};
} // namespace detail

template <class M>
concept ElementModel = requires(const M& model) { model.families(); } &&
  detail::AreElementFamilies<decltype(std::declval<const M&>().families())>::value;

} // namespace softbody

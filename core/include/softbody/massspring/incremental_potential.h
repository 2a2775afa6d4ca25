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
//
// Loads and boundary conditions (scene/boundary_conditions.h) enter as: held components at
// their condition's position at the step's end (fully held points are inactive rows, a
// roller's held components are filtered out by the solver); Force and Pressure as a dead load
// f over the step, the term -f . (x - x0) (Pressure evaluated on the faces at the step's
// start, so the term stays a potential); Pull springs with their energy and the diagonal of
// their Hessian.
//
// The elastic and damping terms come from a material model (material/element_model.h): a list
// of element families, each giving per element its energy, corner gradients and PSD Hessian
// blocks. IncrementalPotential holds what does not depend on the model (inertia, gravity,
// fixed points) and is what the solvers see (implicit_solve.h: one virtual call per evaluation,
// none per element); ModelPotential<Model> runs the element pass, the per-point gather and the
// Hessian assembly generically over the model's families, so a new model needs no code here.
// The spring network's families (material/spring_network.h) are SpringNetworkPotential's.
//
// The order of every sum is fixed and independent of the thread count: element energies are
// summed family by family, element by element; each point gathers its inertial term, then each
// family's contributions in the family's corner order (for the network: Topology::vertexEdges,
// then vertexTetCorners); each Hessian row is written by one task in the same order.
#pragma once

#include "softbody/common/geometry.h"
#include "softbody/common/parallel.h"
#include "softbody/massspring/block_sparse_matrix.h"
#include "softbody/material/element_model.h"
#include "softbody/material/mass.h"
#include "softbody/material/spring_network.h"
#include "softbody/scene/boundary_conditions.h"

#include <cstdint>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace softbody
{

/// The model-independent part of Phi and the interface the implicit solvers use.
class IncrementalPotential
{
public:
  virtual ~IncrementalPotential() = default;
  IncrementalPotential(const IncrementalPotential&) = delete;
  IncrementalPotential& operator=(const IncrementalPotential&) = delete;

  /// The body's loads and boundary conditions (null: none); must outlive this.
  void setConditions(const BoundaryConditions* conditions) { Conditions = conditions; }
  /// Per point, the components held by a condition (empty when none is).
  const std::vector<AxisMask>* heldAxes() const
  {
    return Conditions && !Conditions->heldAxes().empty() ? &Conditions->heldAxes() : nullptr;
  }

  /// Starts a step of h from (x0, v0) at time t0: the inertial target y, the frozen damping
  /// directions, the loads and the held points' positions at t0 + h.
  void beginStep(const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, double h, double t0 = 0.0);

  /// A starting point: the inertial target y = x0 + h v0, plus h^2 g when `withGravity` (the
  /// explicit prediction, exact in free fall); fixed points where they are at the step's end,
  /// held components where their conditions put them.
  void predict(std::vector<Vec3>& x, bool withGravity) const;

  /// Phi(x) [J]; also fills the gradient [N] (zero on fixed points) and keeps the element data
  /// that assembleHessian() reuses.
  virtual double evaluate(const std::vector<Vec3>& x, std::vector<Vec3>& gradient) = 0;

  /// The PSD-projected Hessian at x, which must be the x of the last evaluate(); fixed rows get
  /// the identity. (Only Newton needs it, and only at accepted iterates: evaluate() skips it.)
  /// With `exact` (only where hasExactHessian()), the exact Hessian, which may be indefinite.
  virtual void assembleHessian(const std::vector<Vec3>& x, BlockSparseMatrix& hessian, bool exact = false) = 0;
  /// Whether every element family can give its exact Hessian (the continuum models; not the
  /// spring network, whose volume terms are Gauss-Newton's).
  virtual bool hasExactHessian() const = 0;

  /// Block coordinate descent (vertex_block_descent.h): Phi's gradient and the diagonal 3 x 3
  /// block of its PSD-projected Hessian with respect to point i alone, at positions `y` (point
  /// i's elements evaluated there; the other points are where `y` has them). The loads are
  /// taken as at `evaluated`, the x of the last evaluate(), linearized in y_i (a Pull spring is
  /// linear in its point). Call beginVertexBlocks() after that evaluate(). Reads only: calls
  /// for points of no common element may run in parallel.
  void vertexBlock(std::size_t i, const std::vector<Vec3>& y, const std::vector<Vec3>& evaluated, Vec3& gradient,
    Mat3& hessian) const;
  /// The Pull springs' stiffness at the step's end (for vertexBlock).
  void beginVertexBlocks();

  /// Mass-weighted RMS of the residual acceleration, sqrt(sum_i |G_i|^2 / m_i / sum_i m_i)
  /// [m/s^2]: how far the step's equations are from holding, in the units of g.
  double residualAcceleration(const std::vector<Vec3>& gradient) const;

  /// The acceleration scale the residual is measured against [m/s^2]: the largest of |g|, the
  /// RMS speed at the step's start over h (a body thrown without gravity) and the loads' RMS
  /// acceleration, never 0.
  double referenceAcceleration(double gravityNorm) const;

  /// Drops inertia from Phi: what is left, the elastic energy minus gravity's work, is minimal
  /// at the static equilibrium (the Static integrator). Damping must be off in the model.
  void makeStatic() { Static = true; }
  bool isStatic() const { return Static; }

  const std::vector<char>& active() const { return Active; }
  /// Forces [N] per point that other bodies' contacts put on it over this step, as dead loads
  /// (implicit_solve.cpp carries them from one solve to the next, and owns them); null: none.
  /// beginStep does not clear them.
  void setContactLoads(const std::vector<Vec3>* loads) { ContactLoad = loads; }
  double inverseMass(std::size_t i) const { return InverseMass[i]; }
  std::size_t vertexCount() const { return Active.size(); }
  double step() const { return H; }

protected:
  IncrementalPotential(std::size_t vertexCount, const PointMasses& masses, const Vec3& gravity);

  /// The model's per-step data (its frozen damping directions) from X0 and H.
  virtual void beginElements() = 0;
  /// Adds point i's elements' gradient and diagonal Hessian blocks at y (see vertexBlock).
  virtual void addElementBlock(std::size_t i, const std::vector<Vec3>& y, Vec3& gradient, Mat3& hessian) const = 0;
  /// The inertia and gravity part of Phi(x) [J].
  double inertialEnergy(const std::vector<Vec3>& x) const;
  /// Adds the loads' terms to Phi's gradient at x (zero rows stay zero) and returns their
  /// energy [J]; 0 without loads.
  double addLoadTerms(const std::vector<Vec3>& x, std::vector<Vec3>& gradient);
  /// Adds the Pull springs' diagonal Hessian blocks of the active rows.
  void addLoadHessian(BlockSparseMatrix& hessian);

  static constexpr std::size_t kElementGrain = 2048;
  static constexpr std::size_t kVertexGrain = 512;

  const std::vector<double>& InverseMass;
  Vec3 Gravity;
  std::vector<char> Active; ///< free points (inverse mass > 0)
  double ActiveMass = 0.0;
  bool Static = false; ///< no inertia (makeStatic)
  const BoundaryConditions* Conditions = nullptr;

  // Per step
  double H = 0.0;
  double SpeedScale = 0.0; ///< mass-weighted RMS speed at the step's start [m/s]
  double LoadScale = 0.0;  ///< mass-weighted RMS acceleration of the loads at the start [m/s^2]
  double EndTime = 0.0;    ///< t0 + h: when the held points must be where Target has them
  std::vector<Vec3> X0, Target; ///< x0 and y (for held points: where they are at EndTime)
  std::vector<Vec3> DeadLoad, PullForce; ///< [N]
  const std::vector<Vec3>* ContactLoad = nullptr; ///< [N]; null: none
  std::vector<double> PullStiffness; ///< [N/m]
};

/// Phi with the elastic and damping terms of `Model`'s element families.
template <ElementModel Model>
class ModelPotential final : public IncrementalPotential
{
public:
  /// `topology` gives the Hessian's pattern (BlockSparseMatrix) and must outlive this.
  ModelPotential(const Topology& topology, Model model, const PointMasses& masses,
    const Vec3& gravity)
    : IncrementalPotential(topology.vertexCount, masses, gravity)
    , Topo(topology)
    , Elements(std::move(model))
  {
  }

  double evaluate(const std::vector<Vec3>& x, std::vector<Vec3>& gradient) override;
  void assembleHessian(const std::vector<Vec3>& x, BlockSparseMatrix& hessian, bool exact = false) override;
  bool hasExactHessian() const override
  {
    return []<std::size_t... I>(std::index_sequence<I...>) {
      return (softbody::hasExactHessian<std::remove_cvref_t<std::tuple_element_t<I, Families>>>() && ...);
    }(std::make_index_sequence<kFamilyCount>{});
  }

private:
  void addElementBlock(std::size_t i, const std::vector<Vec3>& y, Vec3& gradient, Mat3& hessian) const override;
  /// body(family, data) for each family, in the model's order, reading only.
  template <class Function>
  void forEachFamilyConst(Function&& body) const
  {
    const Families families = Elements.families();
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      (body(std::get<I>(families), std::get<I>(Data)), ...);
    }(std::make_index_sequence<kFamilyCount>{});
  }

  /// What the potential keeps of one family: per step, per evaluate() and per assembly.
  template <class F>
  struct FamilyData
  {
    std::vector<typename F::StepData> step;       ///< from x0, made by beginStep()
    std::vector<typename F::AtX> atX;             ///< at the last evaluate()'s x
    std::vector<typename F::HessianData> hessian; ///< at the last assembleHessian()'s x
    /// Block slot of (corner a, corner b != a) of each element, at
    /// (e * kCorners + a) * (kCorners - 1) + (b < a ? b : b - 1); found once.
    std::vector<std::int32_t> slots;
  };
  template <class Tuple>
  struct DataOf;
  template <class... F>
  struct DataOf<std::tuple<F...>>
  {
    using type = std::tuple<FamilyData<std::remove_cvref_t<F>>...>;
  };
  using Families = decltype(std::declval<const Model&>().families());
  static constexpr std::size_t kFamilyCount = std::tuple_size_v<Families>;

  /// body(family, data) for each family, in the model's order.
  template <class Function>
  void forEachFamily(Function&& body)
  {
    const Families families = Elements.families();
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      (body(std::get<I>(families), std::get<I>(Data)), ...);
    }(std::make_index_sequence<kFamilyCount>{});
  }

  void beginElements() override;
  template <class F>
  void findSlots(const F& family, FamilyData<F>& data, const BlockSparseMatrix& hessian) const;

  const Topology& Topo;
  Model Elements;
  typename DataOf<Families>::type Data;
  std::vector<double> ElementEnergy; ///< per element of each family in turn, summed in order
};

/// The spring network's potential (Implicit Euler and Projective Dynamics use it).
using SpringNetworkPotential = ModelPotential<SpringNetwork>;

template <ElementModel Model>
void ModelPotential<Model>::beginElements()
{
  forEachFamily([&](const auto& family, auto& data) {
    data.step.resize(family.size());
    parallelFor(family.size(), kElementGrain,
      [&](std::size_t e) { data.step[e] = family.stepData(e, X0); });
  });
}

template <ElementModel Model>
void ModelPotential<Model>::addElementBlock(std::size_t i, const std::vector<Vec3>& y, Vec3& gradient, Mat3& hessian) const
{
  // Each element of the point evaluated afresh at y for this corner alone (Chen et al. 2024
  // evaluate an element once per corner too): the others' positions may have moved since.
  const StepStart start{ X0, H };
  forEachFamilyConst([&](const auto& family, const auto& data) {
    using Family = std::remove_cvref_t<decltype(family)>;
    family.forEachCorner(static_cast<std::int32_t>(i), [&](std::size_t e, int a) {
      typename Family::AtX atX;
      family.evaluate(e, y, start, data.step[e], atX);
      gradient += family.cornerGradient(data.step[e], atX, a);
      const typename Family::HessianData local = family.hessianData(e, y, start, data.step[e], atX);
      hessian += family.hessianBlock(data.step[e], atX, local, a, a);
    });
  });
}

template <ElementModel Model>
double ModelPotential<Model>::evaluate(const std::vector<Vec3>& x, std::vector<Vec3>& gradient)
{
  const StepStart start{ X0, H };
  if constexpr (requires { Elements.beginEvaluate(x); })
  {
    Elements.beginEvaluate(x); // what the elements share beyond themselves (the nodal pressure)
  }
  std::size_t elementCount = 0;
  forEachFamily([&](const auto& family, auto&) { elementCount += family.size(); });
  ElementEnergy.resize(elementCount);
  std::size_t offset = 0;
  forEachFamily([&](const auto& family, auto& data) {
    data.atX.resize(family.size());
    double* energy = ElementEnergy.data() + offset;
    parallelFor(family.size(), kElementGrain, [&](std::size_t e) {
      energy[e] = family.evaluate(e, x, start, data.step[e], data.atX[e]);
    });
    offset += family.size();
  });
  const double h2 = H * H;
  gradient.resize(x.size());
  parallelFor(x.size(), kVertexGrain, [&](std::size_t i) {
    if (!Active[i])
    {
      gradient[i].setZero();
      return;
    }
    const double m = 1.0 / InverseMass[i];
    Vec3 sum = Static ? Vec3(-m * Gravity) : Vec3(m * ((x[i] - Target[i]) / h2 - Gravity));
    forEachFamily([&](const auto& family, auto& data) {
      family.forEachCorner(static_cast<std::int32_t>(i), [&](std::size_t e, int a) {
        sum += family.cornerGradient(data.step[e], data.atX[e], a);
      });
    });
    gradient[i] = sum;
  });
  const double inertia = inertialEnergy(x);
  const double loads = addLoadTerms(x, gradient);
  double shared = 0.0;
  if constexpr (requires { Elements.globalEnergy(); })
  {
    shared = Elements.globalEnergy();
  }
  return inertia + parallelSum(ElementEnergy.size(), [&](std::size_t e) { return ElementEnergy[e]; }) +
    shared + loads;
}

template <ElementModel Model>
template <class F>
void ModelPotential<Model>::findSlots(
  const F& family, FamilyData<F>& data, const BlockSparseMatrix& hessian) const
{
  // Each element corner's off-diagonal blocks, found once: the assembly then writes without
  // looking up edges.
  constexpr int n = F::kCorners;
  data.slots.resize(family.size() * static_cast<std::size_t>(n * (n - 1)));
  parallelFor(family.size(), kElementGrain, [&](std::size_t e) {
    const std::array<std::int32_t, n> corners = family.corners(e);
    std::size_t k = e * static_cast<std::size_t>(n * (n - 1));
    for (int a = 0; a < n; ++a)
    {
      for (int b = 0; b < n; ++b)
      {
        if (b != a)
        {
          data.slots[k++] =
            hessian.edgeSlot(static_cast<std::size_t>(family.edgeBetween(e, a, b)),
              corners[static_cast<std::size_t>(a)], Topo);
        }
      }
    }
  });
}

template <ElementModel Model>
void ModelPotential<Model>::assembleHessian(
  const std::vector<Vec3>& x, BlockSparseMatrix& hessian, bool exact)
{
  const StepStart start{ X0, H, exact && hasExactHessian() };
  forEachFamily([&](const auto& family, auto& data) {
    using F = std::remove_cvref_t<decltype(family)>;
    data.hessian.resize(family.size());
    parallelFor(family.size(), kElementGrain, [&](std::size_t e) {
      data.hessian[e] = family.hessianData(e, x, start, data.step[e], data.atX[e]);
    });
    if (data.slots.size() != family.size() * static_cast<std::size_t>(F::kCorners * (F::kCorners - 1)))
    {
      findSlots(family, data, hessian);
    }
  });
  const double h2 = H * H;
  parallelFor(Topo.vertexCount, kVertexGrain, [&](std::size_t i) {
    Mat3& diagonal = hessian.block(hessian.diagonalSlot(i));
    const std::int32_t rowEnd = hessian.rowStart(i + 1);
    if (!Active[i])
    {
      diagonal.setIdentity();
      for (std::int32_t slot = hessian.diagonalSlot(i) + 1; slot < rowEnd; ++slot)
      {
        hessian.block(slot).setZero();
      }
      return;
    }
    diagonal = Static ? Mat3::Zero() : Mat3(Mat3::Identity() / (h2 * InverseMass[i]));
    // The off-diagonal blocks start at -0, the exact identity of IEEE addition (x + -0 = x for
    // every x, +0 included), so a block written by one element holds that element's value to
    // the last bit, sign of zero included.
    for (std::int32_t slot = hessian.diagonalSlot(i) + 1; slot < rowEnd; ++slot)
    {
      hessian.block(slot).setConstant(-0.0);
    }
    forEachFamily([&](const auto& family, auto& data) {
      using F = std::remove_cvref_t<decltype(family)>;
      constexpr int n = F::kCorners;
      family.forEachCorner(static_cast<std::int32_t>(i), [&](std::size_t e, int a) {
        const auto& step = data.step[e];
        const auto& at = data.atX[e];
        const auto& local = data.hessian[e];
        diagonal += family.hessianBlock(step, at, local, a, a);
        const std::int32_t* slots =
          data.slots.data() +
          (e * static_cast<std::size_t>(n) + static_cast<std::size_t>(a)) * static_cast<std::size_t>(n - 1);
        for (int b = 0, k = 0; b < n; ++b)
        {
          if (b != a)
          {
            hessian.block(slots[k++]) += family.hessianBlock(step, at, local, a, b);
          }
        }
      });
    });
  });
  if constexpr (requires { Elements.addCoupling(x, Active, hessian); })
  {
    Elements.addCoupling(x, Active, hessian);
  }
  addLoadHessian(hessian);
}

} // namespace softbody

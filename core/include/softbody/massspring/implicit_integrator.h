// The implicit integrators as interchangeable strategies. Each solves one step of h through the
// shared line-search solve (implicit_solve.h) with its own direction rule; the mass-spring
// stepper holds one of them and asks nothing about which. A new implicit integrator derives
// from ImplicitIntegrator, gets its row in the integrator table (integrators/integrator.h)
// and its line in makeImplicitIntegrator.
#pragma once

#include "softbody/common/state.h"
#include "softbody/common/step_plan.h"
#include "softbody/massspring/contact_planes.h"
#include "softbody/massspring/implicit_convergence.h"
#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/massspring/model_potential_factory.h"
#include "softbody/material/mass.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace softbody
{

class CoordinatePreconditioner;

class ImplicitIntegrator
{
public:
  virtual ~ImplicitIntegrator() = default;
  /// One step of h (positions and velocities; time and counters are the caller's). Times its
  /// element passes as Stage::Forces and its solves as Stage::LinearSolve.
  virtual void step(double h, DynamicState& state, StepPlan& plan) = 0;
  virtual const ImplicitConvergence& convergence() const = 0;
  ImplicitConvergence& convergence()
  {
    return const_cast<ImplicitConvergence&>(std::as_const(*this).convergence());
  }
  /// The incremental potential the steps minimize (its loads and held points are set on it).
  virtual IncrementalPotential& potential() = 0;
  /// The contact planes the steps keep points on (the floor's; the owner adds the obstacles'
  /// before each step).
  virtual ContactPlanes& contactPlanes() = 0;
  /// Why the solve runs other than asked (a preconditioner that could not be factored), quoting
  /// the cause; empty when it runs as asked. The owner reports it once.
  virtual std::string solverWarning() const { return {}; }
  /// The coordinate preconditioner of the Newton solves, when one is used (its factor's facts).
  virtual const CoordinatePreconditioner* coordinatePreconditioner() const { return nullptr; }
};

/// The strategy for scene.integrator (which must be implicit), over the prepared body.
/// `scene` is the solve's scene: its floor is where contacts hold points. `positions` are the
/// body's starting positions (the static solve checks that its fixed points hold it).
/// `conditions` (null: none) are the body's loads and held points; they must outlive it.
std::unique_ptr<ImplicitIntegrator> makeImplicitIntegrator(const SceneSettings& scene,
  const Topology& topology, const BodyElements& elements, const PointMasses& masses,
  const std::vector<Vec3>& restPositions, const std::vector<Vec3>& positions,
  const BoundaryConditions* conditions = nullptr);

} // namespace softbody

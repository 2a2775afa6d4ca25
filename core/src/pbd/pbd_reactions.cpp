// PbdSimulation: what the supports exert on the points a condition holds.
//
// A compliant XPBD constraint is the energy C^2 / (2 alpha): its force on a corner is
// -(C / alpha) dC/dx, a function of the state alone. (Its multiplier gives the same force once
// the solve has converged, C + alpha lambda / h^2 = 0, but the multipliers are not part of the
// state a frame is restored from.) Those forces are the body's internal forces, and a held
// point's reaction is then what BoundaryConditions::readout makes of them, as for Mass-Spring:
// m (a_prescribed - g) - internal - loads on its held components. Velocity damping scales the
// velocities as a whole and is no internal force; soft pins are constraints, not supports.
//
// PBD's stiffnesses, and XPBD's rigid constraints, define no force of the state. There the
// internal force is what the projections did: a Gauss-Seidel projection moves corner k by
// w_k dC/dx_k dLambda, the momentum dC/dx_k dLambda / h, so over a substep the constraint gave
// each corner, the held ones included, the force lambda dC/dx_k / h^2 (XPBD's force once
// converged, as above). The gradient is taken at the substep's end; it moved by the substep's
// corrections, which is the accuracy of these reactions. They are state (snapshotted with
// the frame) since the multipliers are not.
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/common/geometry.h"
#include "softbody/material/tet_elastic_forces.h"

#include <array>

#include <cmath>

namespace softbody
{
namespace
{

/// A batch's per-element compliance as the step uses it (pbd_simulation.cpp's parameters).
double complianceOf(const std::vector<double>& perElement, std::size_t c, double uniform, double factor = 1.0)
{
  return perElement.empty() ? uniform / factor : perElement[c];
}

} // namespace

bool PbdSimulation::constraintsHaveForces() const
{
  if (Settings.formulation != PbdFormulation::Xpbd)
  {
    return false; // PBD's stiffness in [0, 1] is no force
  }
  if (Plan.runs(Stage::SolveLinks))
  {
    for (std::size_t c = 0; c < Links.size(); ++c)
    {
      if (!(complianceOf(Links.compliance, c, Settings.links.compliance, Links.stiffnessScale[c]) > 0.0))
      {
        return false;
      }
    }
  }
  if (Plan.runs(Stage::SolveVolumes))
  {
    for (std::size_t c = 0; c < Volumes.size(); ++c)
    {
      if (!(complianceOf(Volumes.compliance, c, Settings.volumes.compliance) > 0.0))
      {
        return false;
      }
    }
  }
  return true; // a continuum tet's compliances come from E and nu, always positive
}

void PbdSimulation::elasticForces(const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  forces.assign(x.size(), Vec3::Zero());
  if (TetElastic.size() > 0)
  {
    TetElasticScratch scratch;
    const std::vector<Vec3> still(x.size(), Vec3::Zero());
    computeTetElasticForces(ElasticTopology, ElasticConstants, x, still, scratch, forces);
  }
  // Edge links and volumes, in storage order (one pass; a frame's read-out, not a step).
  if (Plan.runs(Stage::SolveLinks))
  {
    for (std::size_t c = 0; c < Links.size(); ++c)
    {
      const double alpha = complianceOf(Links.compliance, c, Settings.links.compliance, Links.stiffnessScale[c]);
      if (!Links.active(c) || !std::isfinite(alpha))
      {
        continue;
      }
      const auto& e = Links.ends[c];
      const Vec3 d = x[e[0]] - x[e[1]];
      const double length = d.norm();
      double C = length - Links.rest[c];
      if (Links.kind == DistanceKind::AtLeast && C > 0.0)
      {
        C = 0.0;
      }
      if (length > 0.0)
      {
        const Vec3 f = -(C / alpha) * (d / length);
        forces[e[0]] += f;
        forces[e[1]] -= f;
      }
    }
  }
  if (Plan.runs(Stage::SolveVolumes))
  {
    for (std::size_t c = 0; c < Volumes.size(); ++c)
    {
      const double alpha = complianceOf(Volumes.compliance, c, Settings.volumes.compliance);
      if (!Volumes.active(c) || !std::isfinite(alpha))
      {
        continue;
      }
      const Tet& t = Volumes.tets[c];
      const Vec3 e1 = x[t[1]] - x[t[0]], e2 = x[t[2]] - x[t[0]], e3 = x[t[3]] - x[t[0]];
      const Vec3 g1 = e2.cross(e3) / 6.0, g2 = e3.cross(e1) / 6.0, g3 = e1.cross(e2) / 6.0;
      const double C = e1.dot(e2.cross(e3)) / 6.0 - Volumes.restVolume[c];
      const double push = -C / alpha;
      forces[t[1]] += push * g1;
      forces[t[2]] += push * g2;
      forces[t[3]] += push * g3;
      forces[t[0]] -= push * (g1 + g2 + g3);
    }
  }
}

void PbdSimulation::recordSupportForces(double h)
{
  const std::vector<Vec3>& x = State.positions;
  std::vector<Vec3>& forces = State.supportForces;
  forces.assign(x.size(), Vec3::Zero());
  const double perH2 = 1.0 / (h * h);
  if (Plan.runs(Stage::SolveLinks))
  {
    for (std::size_t c = 0; c < Links.size(); ++c)
    {
      const double lambda = Links.lambda[c];
      const auto& e = Links.ends[c];
      const Vec3 d = x[e[0]] - x[e[1]];
      const double length = d.norm();
      if (lambda != 0.0 && length > 0.0)
      {
        const Vec3 f = (lambda * perH2 / length) * d;
        forces[e[0]] += f;
        forces[e[1]] -= f;
      }
    }
  }
  if (Plan.runs(Stage::SolveVolumes))
  {
    for (std::size_t c = 0; c < Volumes.size(); ++c)
    {
      const double push = Volumes.lambda[c] * perH2;
      if (push == 0.0)
      {
        continue;
      }
      const Tet& t = Volumes.tets[c];
      const std::array<Vec3, 4> g = tetVolumeGradients(x[t[0]], x[t[1]], x[t[2]], x[t[3]]);
      for (int k = 0; k < 4; ++k)
      {
        forces[t[k]] += push * g[k];
      }
    }
  }
}

ConditionReadout PbdSimulation::conditionReadout() const
{
  if (Conditions.empty())
  {
    return {};
  }
  std::vector<Vec3> internal;
  if (constraintsHaveForces())
  {
    elasticForces(State.positions, internal);
  }
  else if (!ReactionsFromMultipliers)
  {
    return {};
  }
  else if (State.supportForces.size() == State.positions.size())
  {
    internal = State.supportForces;
  }
  else
  {
    internal.assign(State.positions.size(), Vec3::Zero()); // before the first step: no projection yet
  }
  return Conditions.readout(State.time, State.positions, internal, PointMass, Settings.gravity);
}

} // namespace softbody

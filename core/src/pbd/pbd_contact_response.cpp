// PbdSimulation's velocity pass at the contacts: restitution along each contact's normal,
// point by point and for whole bodies. (Friction acts in the solve, at the position level:
// pbd_contact_kernels.h.)
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/collision/contact_terms.h"
#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"

#include <algorithm>
#include <cmath>

namespace softbody
{

void PbdSimulation::applyContactResponse(double h)
{
  ScopedStageTimer timer(Plan, Stage::ContactResponse);
  // Below this approach speed a contact is resting: bouncing it would make bodies jitter.
  const double restingSpeed = 2.0 * Settings.gravity.norm() * h;
  const double e = Settings.collisions.restitution;
  std::vector<Vec3>& v = State.velocities;
  // Obstacle contacts: the normal speed relative to the surface leaves at e times the one it
  // arrived with (one point each, one task per point, as in the solve).
  parallelFor(ObstacleGroups.size() - 1, 256, [&](std::size_t g) {
    for (std::size_t k = ObstacleGroups[g]; k < ObstacleGroups[g + 1]; ++k)
    {
      const Contact& c = Contacts[k];
      if (c.kind != ContactKind::Obstacle)
      {
        break;
      }
      if (ContactLambda[k].normal <= 0.0)
      {
        continue; // never pushed: a speculative contact
      }
      const std::size_t i = static_cast<std::size_t>(c.point);
      if (InverseMass[i] == 0.0)
      {
        continue;
      }
      const double surface = c.normal.dot(c.surfaceVelocity);
      v[i] += restitutionSpeedChange(c.normal.dot(VelocityBefore[i]) - surface,
                c.normal.dot(v[i]) - surface, e, restingSpeed) * c.normal;
    }
  });
  // Body contacts: the relative normal speed, the change shared as the position corrections
  // were (c_k w_k / W), so momentum is kept.
  for (std::size_t k : BodyContacts)
  {
    const Contact& c = Contacts[k];
    if (ContactLambda[k].normal <= 0.0)
    {
      continue;
    }
    const ContactTerms p = termsOf(c);
    Vec3 n = c.normal;
    if (c.kind == ContactKind::PointPoint)
    {
      const Vec3 r = State.positions[p.index[0]] - State.positions[p.index[1]];
      n = r.norm() > 0.0 ? Vec3(r.normalized()) : c.normal;
    }
    double approach = 0.0, now = 0.0, W = 0.0;
    for (int j = 0; j < p.count; ++j)
    {
      const auto i = static_cast<std::size_t>(p.index[j]);
      approach += p.coefficient[j] * n.dot(VelocityBefore[i]);
      now += p.coefficient[j] * n.dot(v[i]);
      W += p.coefficient[j] * p.coefficient[j] * InverseMass[i];
    }
    const double change = restitutionSpeedChange(approach, now, e, restingSpeed);
    if (change > 0.0 && W > 0.0)
    {
      for (int j = 0; j < p.count; ++j)
      {
        const auto i = static_cast<std::size_t>(p.index[j]);
        v[i] += (p.coefficient[j] * InverseMass[i] / W * change) * n;
      }
    }
  }
  applyBodyRestitution(h);
}

void PbdSimulation::applyBodyRestitution(double h)
{
  // Restitution point by point is exact only where a body's points all hit at once (a flat
  // cloth, loose particles). A tet body hits with its bottom layer: those points leave at e v,
  // the constraints give that momentum back to the rest of the body, which still moves down,
  // and the body comes to rest over a few substeps whatever e is. So restitution also acts on
  // whole bodies: when a body first touches an obstacle (the floor included) while its centre
  // of mass approaches faster than the resting speed, that speed I and the direction it hit
  // along (the mean normal of its obstacle contacts) are recorded; when the body has left
  // again or has stopped on it (two substeps in a row), its centre of mass gets the normal
  // speed it lacks to leave at e I. It only adds: a body that bounces by its own elasticity
  // keeps it. Bodies meeting bodies are left to the point-wise pass. The speeds are relative
  // to the obstacle's normal speed where the body touches it now.
  const double restingSpeed = 2.0 * Settings.gravity.norm() * h;
  const double e = Settings.collisions.restitution;
  const std::size_t bodies = BodyFirstPoint.size();
  std::vector<Vec3> normalSum(bodies, Vec3::Zero());
  std::vector<double> surfaceSpeed(bodies, 0.0);
  std::vector<int> touches(bodies, 0);
  for (std::size_t k = 0; k < Contacts.size(); ++k)
  {
    const Contact& c = Contacts[k];
    if (c.kind == ContactKind::Obstacle && ContactLambda[k].normal > 0.0)
    {
      const std::int32_t b = BodyOf[static_cast<std::size_t>(c.point)];
      normalSum[b] += c.normal;
      surfaceSpeed[b] += c.normal.dot(c.surfaceVelocity);
      ++touches[b];
    }
  }
  std::vector<Vec3> normal(bodies, Vec3::Zero());
  for (std::size_t b = 0; b < bodies; ++b)
  {
    const std::size_t first = static_cast<std::size_t>(BodyFirstPoint[b]);
    if (touches[b] > 0 && normalSum[b].norm() > 0.0)
    {
      normal[b] = normalSum[b].normalized();
      surfaceSpeed[b] /= touches[b];
    }
    else
    {
      normal[b] = State.impactNormals[first]; // left: the direction it hit along (or zero)
      touches[b] = 0;
    }
  }
  std::vector<double> mass(bodies, 0.0), before(bodies, 0.0), after(bodies, 0.0);
  std::vector<char> held(bodies, 0);
  for (std::size_t i = 0; i < State.positions.size(); ++i)
  {
    const std::int32_t b = BodyOf[i];
    if (InverseMass[i] == 0.0)
    {
      held[b] = 1;
      continue;
    }
    const double m = 1.0 / InverseMass[i];
    mass[b] += m;
    before[b] += m * VelocityBefore[i].dot(normal[b]);
    after[b] += m * State.velocities[i].dot(normal[b]);
  }
  std::vector<double> boost(bodies, 0.0), impact(bodies, 0.0);
  for (std::size_t b = 0; b < bodies; ++b)
  {
    if (held[b] || mass[b] == 0.0 || normal[b] == Vec3::Zero())
    {
      normal[b].setZero();
      continue;
    }
    const double vBefore = before[b] / mass[b] - surfaceSpeed[b];
    const double vAfter = after[b] / mass[b] - surfaceSpeed[b];
    const bool touching = touches[b] > 0;
    double speed = State.impactSpeeds[static_cast<std::size_t>(BodyFirstPoint[b])];
    if (speed == 0.0 && touching && vBefore < -restingSpeed)
    {
      speed = -vBefore;
    }
    if (speed != 0.0 && vAfter > -restingSpeed)
    {
      const double I = std::abs(speed);
      const bool stopped = touching && vAfter < restingSpeed;
      if (!touching || (stopped && speed < 0.0))
      {
        const double add = e * I - vAfter;
        boost[b] = add > 1e-6 * I ? add : 0.0;
        speed = 0.0;
      }
      else
      {
        speed = stopped ? -I : I; // stopped once: wait one substep (a rebound passes zero)
      }
    }
    impact[b] = speed;
    if (speed == 0.0 && boost[b] == 0.0)
    {
      normal[b].setZero(); // nothing pending: forget the direction
    }
  }
  for (std::size_t i = 0; i < State.positions.size(); ++i)
  {
    const std::int32_t b = BodyOf[i];
    State.impactSpeeds[i] = impact[b];
    State.impactNormals[i] = impact[b] != 0.0 ? normal[b] : Vec3::Zero();
    if (boost[b] != 0.0 && InverseMass[i] > 0.0)
    {
      State.velocities[i] += boost[b] * normal[b];
    }
  }
}

} // namespace softbody

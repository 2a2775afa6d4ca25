#include "softbody/massspring/contact_response.h"

#include "softbody/collision/contact_terms.h"
#include "softbody/collision/coulomb_friction.h"
#include "softbody/common/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace softbody
{
namespace
{

/// Projection and velocity response of one contact (contact_response.h); true if it was
/// penetrating.
bool resolveContact(const Contact& contact, const CollisionSettings& settings,
  const std::vector<double>& w, const std::vector<Vec3>& start, double h,
  std::vector<Vec3>& x, std::vector<Vec3>& v)
{
  const ContactTerms t = termsOf(contact);
  double W = 0.0;
  Vec3 gap = contact.kind == ContactKind::Obstacle ? Vec3(-contact.surfacePoint) : Vec3::Zero();
  for (int j = 0; j < t.count; ++j)
  {
    W += t.coefficient[j] * t.coefficient[j] * w[t.index[j]];
    gap += t.coefficient[j] * x[t.index[j]];
  }
  if (W <= 0.0)
  {
    return false; // everything involved is pinned
  }
  Vec3 n = contact.normal;
  if (contact.kind == ContactKind::PointPoint && gap.norm() > 0.0)
  {
    n = gap.normalized(); // spheres: C = |x_p - x_o| - thickness, exact rather than linearized
  }
  const double C = n.dot(gap) - contact.thickness;
  if (C >= 0.0)
  {
    return false;
  }

  // 1. Position: the smallest mass-weighted move onto C = 0.
  const double lambda = -C / W;
  for (int j = 0; j < t.count; ++j)
  {
    x[t.index[j]] += (t.coefficient[j] * w[t.index[j]] * lambda) * n;
  }

  // 2. Velocity: restitution on the approach speed, Coulomb friction on the slip.
  Vec3 relative = -contact.surfaceVelocity;
  for (int j = 0; j < t.count; ++j)
  {
    relative += t.coefficient[j] * v[t.index[j]];
  }
  const double normalSpeed = n.dot(relative);
  // Restitution acts on an approach; friction on the normal push of the contact: the approach
  // speed removed, or the penetration removed per unit time where that is larger. The second
  // is what carries a load between two bodies that fall together (a body resting on another:
  // both gain g h each step, so their relative approach is nil while the lower one holds the
  // upper one up through the projection); against a static surface both are g h per step.
  const double normalChange = normalSpeed < 0.0 ? -(1.0 + settings.restitution) * normalSpeed : 0.0;
  const double normalPush = std::max(normalChange, -C / h);
  bool sticks = false;
  const Vec3 change =
    normalChange * n + coulombFrictionChange(relative - normalSpeed * n, normalPush, settings, sticks);
  for (int j = 0; j < t.count; ++j)
  {
    v[t.index[j]] += (t.coefficient[j] * w[t.index[j]] / W) * change;
  }
  if (sticks)
  {
    // Static friction holds the positions too: without this the slip of the step before the
    // velocity was cancelled (g sin(theta) h^2 each step) would creep down any slope.
    Vec3 slip = -h * contact.surfaceVelocity;
    for (int j = 0; j < t.count; ++j)
    {
      slip += t.coefficient[j] * (x[t.index[j]] - start[t.index[j]]);
    }
    const Vec3 tangentialSlip = slip - n.dot(slip) * n;
    for (int j = 0; j < t.count; ++j)
    {
      x[t.index[j]] -= (t.coefficient[j] * w[t.index[j]] / W) * tangentialSlip;
    }
  }
  return true;
}

/// Signed distance of the point's start to the contact's plane at the step's start (the
/// obstacle moved by surfaceVelocity h during the step): < 0 means it started behind.
double startSide(const Contact& contact, const std::vector<Vec3>& start, double h)
{
  return contact.normal.dot(start[contact.point] - (contact.surfacePoint - h * contact.surfaceVelocity));
}

} // namespace

ContactResponseStats respondToContacts(const ContactSet& contacts, const CollisionSettings& settings,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& start, double h,
  std::vector<Vec3>& positions, std::vector<Vec3>& velocities)
{
  ContactResponseStats stats;
  // The contacts are sorted by point, then kind (Obstacle first): each point's obstacle
  // contacts form one run, and runs touch disjoint points.
  std::vector<std::size_t> runs;
  std::size_t bodyContacts = 0;
  for (std::size_t k = 0; k < contacts.size(); ++k)
  {
    if (contacts[k].kind != ContactKind::Obstacle)
    {
      ++bodyContacts;
    }
    else if (k == 0 || contacts[k - 1].kind != ContactKind::Obstacle ||
      contacts[k - 1].point != contacts[k].point)
    {
      runs.push_back(k);
    }
  }
  struct RunStats
  {
    std::size_t projected = 0;
    std::size_t ignored = 0;
  };
  std::vector<RunStats> runStats(runs.size());
  parallelFor(runs.size(), 64, [&](std::size_t r) {
    std::size_t end = runs[r];
    bool startsInFront = false;
    while (end < contacts.size() && contacts[end].kind == ContactKind::Obstacle &&
      contacts[end].point == contacts[runs[r]].point)
    {
      startsInFront = startsInFront || startSide(contacts[end], start, h) >= 0.0;
      ++end;
    }
    for (std::size_t k = runs[r]; k < end; ++k)
    {
      if (startsInFront && startSide(contacts[k], start, h) < 0.0)
      {
        ++runStats[r].ignored;
        continue;
      }
      runStats[r].projected +=
        resolveContact(contacts[k], settings, inverseMass, start, h, positions, velocities) ? 1 : 0;
    }
  });
  for (const RunStats& s : runStats)
  {
    stats.projected += s.projected;
    stats.ignored += s.ignored;
  }
  if (bodyContacts > 0)
  {
    // Body contacts share points (a triangle's corners are other contacts' points): in order.
    for (const Contact& contact : contacts)
    {
      if (contact.kind != ContactKind::Obstacle &&
        resolveContact(contact, settings, inverseMass, start, h, positions, velocities))
      {
        ++stats.projected;
      }
    }
  }
  return stats;
}

} // namespace softbody

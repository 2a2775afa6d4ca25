#include "softbody/scene/boundary_conditions.h"

#include "softbody/collision/boundary_triangles.h"
#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>

namespace softbody
{
namespace
{

constexpr double kStandardGravity = 9.80665;   // [m/s^2]
constexpr double kWarnedAcceleration = 1000.0; // [g]

std::string named(const Condition& c)
{
  return "Condition '" + c.name + "' (" + conditionKindName(c.kind) + ")";
}

Vec3 faceAreaVector(const std::array<std::int32_t, 3>& f, const std::vector<Vec3>& x)
{
  const Vec3& a = x[static_cast<std::size_t>(f[0])];
  return 0.5 * (x[static_cast<std::size_t>(f[1])] - a).cross(x[static_cast<std::size_t>(f[2])] - a);
}

} // namespace

/// x(t) = c + R(s angle) (X - c) + s T for a rest point X, with its first two time derivatives.
struct BoundaryConditions::Motion
{
  const Condition& c;
  double t;

  Vec3 axis() const
  {
    return c.rotationAngle != 0.0 ? Vec3(c.rotationAxis.normalized()) : Vec3::UnitZ();
  }
  Vec3 arm(const Vec3& rest) const
  {
    const double angle = c.profile.at(t) * c.rotationAngle;
    if (angle == 0.0)
    {
      return rest - c.rotationCenter;
    }
    return Eigen::AngleAxisd(angle, axis()) * (rest - c.rotationCenter);
  }
  Vec3 position(const Vec3& rest) const
  {
    return c.rotationCenter + arm(rest) + c.profile.at(t) * c.translation;
  }
  Vec3 velocity(const Vec3& rest) const
  {
    return c.profile.rate(t) * (c.rotationAngle * axis().cross(arm(rest)) + c.translation);
  }
  Vec3 acceleration(const Vec3& rest) const
  {
    const Vec3 r = arm(rest), a = axis();
    const double spin = c.profile.rate(t) * c.rotationAngle;
    return c.profile.acceleration(t) * (c.rotationAngle * a.cross(r) + c.translation) +
      spin * spin * a.cross(a.cross(r));
  }
};

BoundaryConditions::BoundaryConditions(std::vector<Condition> conditions,
  const std::vector<Vec3>& restPoints, const std::vector<Tet>& tets, double totalMass,
  std::vector<std::string>& warnings)
  : Conditions(std::move(conditions))
  , Rest(restPoints)
{
  validateConditions(Conditions, Rest.size(), warnings);
  const std::size_t n = Rest.size();
  std::vector<std::array<std::int32_t, 3>> surface;
  bool surfaceFound = false;
  Faces.resize(Conditions.size());
  Weights.resize(Conditions.size());
  std::vector<char> inSet(n, 0);
  for (std::size_t ci = 0; ci < Conditions.size(); ++ci)
  {
    const Condition& c = Conditions[ci];
    if (c.holds())
    {
      if (Held.empty())
      {
        Held.assign(n, 0);
        HeldBy.assign(n, { -1, -1, -1 });
      }
      for (std::int32_t p : c.points)
      {
        for (std::size_t axis = 0; axis < 3; ++axis)
        {
          if (c.heldAxes[axis])
          {
            Held[static_cast<std::size_t>(p)] |= static_cast<AxisMask>(1u << axis);
            if (HeldBy[static_cast<std::size_t>(p)][axis] < 0)
            {
              HeldBy[static_cast<std::size_t>(p)][axis] = static_cast<std::int32_t>(ci);
            }
          }
        }
      }
      MovesPoints = MovesPoints || (c.kind == ConditionKind::Prescribed && !c.points.empty());
      continue;
    }
    if (c.points.empty())
    {
      continue;
    }
    HasLoads = true;
    const bool onFaces = c.kind == ConditionKind::Pressure ||
      (c.kind == ConditionKind::Force && c.spread == ForceSpread::ByArea);
    if (onFaces)
    {
      if (!surfaceFound)
      {
        surface = boundaryTriangles(tets);
        surfaceFound = true;
      }
      for (std::int32_t p : c.points)
      {
        inSet[static_cast<std::size_t>(p)] = 1;
      }
      for (const auto& f : surface)
      {
        if (inSet[static_cast<std::size_t>(f[0])] && inSet[static_cast<std::size_t>(f[1])] &&
            inSet[static_cast<std::size_t>(f[2])])
        {
          Faces[ci].push_back(f);
        }
      }
      for (std::int32_t p : c.points)
      {
        inSet[static_cast<std::size_t>(p)] = 0;
      }
      if (!Faces[ci].empty())
      {
        gatherFaces(ci);
      }
      if (Faces[ci].empty())
      {
        throw InvalidInputError(named(c) + ": none of the body's boundary faces has all three "
          "corners in its set of " + std::to_string(c.points.size()) + " points, so there is "
          "no area to act on. Select a region of the surface (whole faces), or spread the force "
          "by mass.");
      }
    }
    HasPressure = HasPressure || c.kind == ConditionKind::Pressure;
    if (c.kind == ConditionKind::Pull)
    {
      PullPoints.push_back(ci);
    }
    double loadScale = 0.0; // the largest force it applies [N]
    if (c.kind == ConditionKind::Force)
    {
      loadScale = c.force.norm() *
        (c.spread == ForceSpread::PerPoint ? static_cast<double>(c.points.size()) : 1.0);
    }
    else if (c.kind == ConditionKind::Pressure)
    {
      double area = 0.0;
      for (const auto& f : Faces[ci])
      {
        area += faceAreaVector(f, Rest).norm();
      }
      loadScale = std::abs(c.pressure) * area;
    }
    if (totalMass > 0.0 && loadScale / totalMass > kWarnedAcceleration * kStandardGravity)
    {
      std::ostringstream s;
      s << named(c) << " applies up to " << loadScale << " N to a body of " << totalMass
        << " kg: an acceleration of " << loadScale / totalMass / kStandardGravity
        << " g. Check the units (newtons, pascals) and the body's density.";
      warnings.push_back(s.str());
    }
  }
}

void BoundaryConditions::gatherFaces(std::size_t k)
{
  FaceGathers.resize(Conditions.size());
  FaceGather& g = FaceGathers[k];
  std::vector<std::int32_t> count(Rest.size(), 0);
  for (const auto& f : Faces[k])
  {
    for (std::int32_t corner : f)
    {
      ++count[static_cast<std::size_t>(corner)];
    }
  }
  std::vector<std::int32_t> slot(Rest.size(), -1);
  g.start.assign(1, 0);
  for (std::size_t i = 0; i < Rest.size(); ++i)
  {
    if (count[i] > 0)
    {
      slot[i] = static_cast<std::int32_t>(g.corner.size());
      g.corner.push_back(static_cast<std::int32_t>(i));
      g.start.push_back(g.start.back() + count[i]);
    }
  }
  g.faces.assign(static_cast<std::size_t>(g.start.back()), 0);
  std::vector<std::int32_t> filled(g.corner.size(), 0);
  for (std::size_t f = 0; f < Faces[k].size(); ++f)
  {
    for (std::int32_t corner : Faces[k][f])
    {
      const std::size_t j = static_cast<std::size_t>(slot[static_cast<std::size_t>(corner)]);
      g.faces[static_cast<std::size_t>(g.start[j] + filled[j]++)] = static_cast<std::int32_t>(f);
    }
  }
}

void BoundaryConditions::setMasses(const std::vector<double>& mass)
{
  Mass = mass;
  for (std::size_t ci = 0; ci < Conditions.size(); ++ci)
  {
    const Condition& c = Conditions[ci];
    std::vector<double>& w = Weights[ci];
    w.assign(c.points.size(), 0.0);
    if (c.holds() || c.kind == ConditionKind::Pressure || c.points.empty())
    {
      continue;
    }
    double total = 0.0;
    if (c.kind == ConditionKind::Force && c.spread == ForceSpread::ByArea)
    {
      std::vector<double> area(Rest.size(), 0.0);
      for (const auto& f : Faces[ci])
      {
        const double third = faceAreaVector(f, Rest).norm() / 3.0;
        for (std::int32_t p : f)
        {
          area[static_cast<std::size_t>(p)] += third;
        }
      }
      for (std::size_t k = 0; k < c.points.size(); ++k)
      {
        w[k] = area[static_cast<std::size_t>(c.points[k])];
        total += w[k];
      }
    }
    else if (c.kind == ConditionKind::Force && c.spread == ForceSpread::PerPoint)
    {
      std::fill(w.begin(), w.end(), 1.0);
      total = 1.0;
    }
    else // ByMass forces and the Pull centroid
    {
      for (std::size_t k = 0; k < c.points.size(); ++k)
      {
        w[k] = Mass[static_cast<std::size_t>(c.points[k])];
        total += w[k];
      }
    }
    if (!(total > 0.0))
    {
      throw InvalidInputError(named(c) + ": its points have no mass (they belong to no tet), so "
        "a force cannot be spread over them.");
    }
    for (double& share : w)
    {
      share /= total;
    }
  }
}

bool BoundaryConditions::sameStructure(const std::vector<Condition>& conditions) const
{
  if (conditions.size() != Conditions.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < conditions.size(); ++k)
  {
    const Condition &a = Conditions[k], &b = conditions[k];
    if (a.kind != b.kind || a.points != b.points || a.heldAxes != b.heldAxes)
    {
      return false;
    }
  }
  return true;
}

void BoundaryConditions::replaceValues(std::vector<Condition> conditions)
{
  if (!sameStructure(conditions))
  {
    throw InvalidInputError("The conditions changed their kind, set or held components, which "
                            "changes the body's held points: the simulation must be built anew.");
  }
  std::vector<std::string> warnings; // said when the body was built
  validateConditions(conditions, Rest.size(), warnings);
  Conditions = std::move(conditions);
  setMasses(Mass);
}

std::vector<char> BoundaryConditions::fullyHeld() const
{
  std::vector<char> full(Rest.size(), 0);
  for (std::size_t i = 0; i < Held.size(); ++i)
  {
    full[i] = Held[i] == kAllAxes ? 1 : 0;
  }
  return full;
}

Vec3 BoundaryConditions::heldPosition(const Condition& c, std::size_t i, double t) const
{
  return c.kind == ConditionKind::Prescribed ? Motion{ c, t }.position(Rest[i]) : Rest[i];
}

void BoundaryConditions::holdPoints(double t, std::vector<Vec3>& x, std::vector<Vec3>& v) const
{
  holdComponents(t, x, &v);
}

void BoundaryConditions::holdPositions(double t, std::vector<Vec3>& x) const
{
  holdComponents(t, x, nullptr);
}

void BoundaryConditions::holdComponents(double t, std::vector<Vec3>& x, std::vector<Vec3>* v) const
{
  for (const Condition& c : Conditions)
  {
    if (!c.holds())
    {
      continue;
    }
    const Motion motion{ c, t };
    for (std::int32_t p : c.points)
    {
      const std::size_t i = static_cast<std::size_t>(p);
      const Vec3 position = heldPosition(c, i, t);
      const Vec3 velocity =
        v && c.kind == ConditionKind::Prescribed ? motion.velocity(Rest[i]) : Vec3::Zero();
      for (int axis = 0; axis < 3; ++axis)
      {
        if (c.heldAxes[static_cast<std::size_t>(axis)])
        {
          x[i][axis] = position[axis];
          if (v)
          {
            (*v)[i][axis] = velocity[axis];
          }
        }
      }
    }
  }
}

void BoundaryConditions::filterHeld(std::vector<Vec3>& a) const
{
  for (std::size_t i = 0; i < Held.size(); ++i)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (Held[i] & (1u << axis))
      {
        a[i][axis] = 0.0;
      }
    }
  }
}

Vec3 BoundaryConditions::heldAcceleration(std::size_t i, double t) const
{
  Vec3 a = Vec3::Zero();
  if (Held.empty())
  {
    return a;
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    const std::int32_t by = HeldBy[i][static_cast<std::size_t>(axis)];
    if (by >= 0 && Conditions[static_cast<std::size_t>(by)].kind == ConditionKind::Prescribed)
    {
      a[axis] = Motion{ Conditions[static_cast<std::size_t>(by)], t }.acceleration(Rest[i])[axis];
    }
  }
  return a;
}

void BoundaryConditions::addPressure(const Condition& c, std::size_t k, double t,
  const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  // p A n over each face, a third to each corner: the exact nodal force of a uniform pressure
  // on a linear triangle. The faces' area vectors in parallel, then each corner gathers its
  // faces' shares in face order (no two tasks write one point).
  const double p = c.pressure * c.profile.at(t);
  const std::vector<std::array<std::int32_t, 3>>& faces = Faces[k];
  FaceArea.resize(faces.size());
  parallelFor(faces.size(), 2048, [&](std::size_t f) { FaceArea[f] = faceAreaVector(faces[f], x); });
  const FaceGather& g = FaceGathers[k];
  parallelFor(g.corner.size(), 2048, [&](std::size_t j) {
    Vec3 sum = Vec3::Zero();
    for (std::int32_t e = g.start[j]; e < g.start[j + 1]; ++e)
    {
      sum += FaceArea[static_cast<std::size_t>(g.faces[static_cast<std::size_t>(e)])];
    }
    forces[static_cast<std::size_t>(g.corner[j])] += (p / 3.0) * sum;
  });
}

void BoundaryConditions::addForce(const Condition& c, std::size_t k, double t,
  std::vector<Vec3>& forces) const
{
  const Vec3 total = c.profile.at(t) * c.force;
  for (std::size_t j = 0; j < c.points.size(); ++j)
  {
    forces[static_cast<std::size_t>(c.points[j])] += Weights[k][j] * total;
  }
}

void BoundaryConditions::deadLoads(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  forces.assign(Rest.size(), Vec3::Zero());
  addForcesAndPressures(t, x, forces);
}

void BoundaryConditions::addForcesAndPressures(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  for (std::size_t k = 0; k < Conditions.size(); ++k)
  {
    const Condition& c = Conditions[k];
    if (c.kind == ConditionKind::Force)
    {
      addForce(c, k, t, forces);
    }
    else if (c.kind == ConditionKind::Pressure)
    {
      addPressure(c, k, t, x, forces);
    }
  }
}

double BoundaryConditions::addPullForces(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  double energy = 0.0;
  for (std::size_t k : PullPoints)
  {
    const Condition& c = Conditions[k];
    Vec3 centroid = Vec3::Zero();
    for (std::size_t j = 0; j < c.points.size(); ++j)
    {
      centroid += Weights[k][j] * x[static_cast<std::size_t>(c.points[j])];
    }
    const double stiffness = c.pullStiffness * c.profile.at(t);
    const Vec3 pull = stiffness * (c.pullTarget - centroid);
    energy += 0.5 * stiffness * (c.pullTarget - centroid).squaredNorm();
    for (std::size_t j = 0; j < c.points.size(); ++j)
    {
      forces[static_cast<std::size_t>(c.points[j])] += Weights[k][j] * pull;
    }
  }
  return energy;
}

void BoundaryConditions::pullStiffness(double t, std::vector<double>& k) const
{
  k.assign(Rest.size(), 0.0);
  for (std::size_t ci : PullPoints)
  {
    const Condition& c = Conditions[ci];
    const double stiffness = c.pullStiffness * c.profile.at(t);
    for (std::size_t j = 0; j < c.points.size(); ++j)
    {
      k[static_cast<std::size_t>(c.points[j])] += stiffness * Weights[ci][j] * Weights[ci][j];
    }
  }
}

void BoundaryConditions::addLoads(double t, const std::vector<Vec3>& x, std::vector<Vec3>& forces) const
{
  addForcesAndPressures(t, x, forces);
  if (!PullPoints.empty())
  {
    addPullForces(t, x, forces);
  }
}

ConditionReadout BoundaryConditions::readout(double t, const std::vector<Vec3>& x,
  const std::vector<Vec3>& internal, const std::vector<double>& mass, const Vec3& gravity) const
{
  ConditionReadout out;
  std::vector<Vec3> loads(x.size(), Vec3::Zero());
  addLoads(t, x, loads);
  if (!Held.empty())
  {
    out.reactions.assign(x.size(), Vec3::Zero());
    for (std::size_t i = 0; i < Held.size(); ++i)
    {
      if (Held[i] == 0)
      {
        continue;
      }
      const Vec3 needed = mass[i] * (heldAcceleration(i, t) - gravity) - internal[i] - loads[i];
      for (int axis = 0; axis < 3; ++axis)
      {
        if (Held[i] & (1u << axis))
        {
          out.reactions[i][axis] = needed[axis];
        }
      }
    }
  }
  std::vector<Vec3> own(x.size(), Vec3::Zero());
  for (std::size_t k = 0; k < Conditions.size(); ++k)
  {
    const Condition& c = Conditions[k];
    ConditionTotal total{ c.name, c.kind, c.points.size() };
    if (c.points.empty())
    {
      out.totals.push_back(total);
      continue;
    }
    for (std::int32_t p : c.points)
    {
      total.center += x[static_cast<std::size_t>(p)];
    }
    total.center /= static_cast<double>(c.points.size());
    // This condition's own force on each point of its set.
    for (std::int32_t p : c.points)
    {
      own[static_cast<std::size_t>(p)].setZero();
    }
    if (c.holds())
    {
      for (std::int32_t p : c.points)
      {
        const std::size_t i = static_cast<std::size_t>(p);
        for (std::size_t axis = 0; axis < 3; ++axis)
        {
          if (HeldBy[i][axis] == static_cast<std::int32_t>(k))
          {
            own[i][static_cast<Eigen::Index>(axis)] = out.reactions[i][static_cast<Eigen::Index>(axis)];
          }
        }
      }
    }
    else if (c.kind == ConditionKind::Force)
    {
      addForce(c, k, t, own);
    }
    else if (c.kind == ConditionKind::Pressure)
    {
      addPressure(c, k, t, x, own);
    }
    else
    {
      BoundaryConditions single;
      single.Conditions = { c };
      single.Weights = { Weights[k] };
      single.PullPoints = { 0 };
      single.addPullForces(t, x, own);
    }
    for (std::int32_t p : c.points)
    {
      const std::size_t i = static_cast<std::size_t>(p);
      total.force += own[i];
      total.moment += (x[i] - total.center).cross(own[i]);
    }
    out.totals.push_back(total);
  }
  return out;
}

} // namespace softbody

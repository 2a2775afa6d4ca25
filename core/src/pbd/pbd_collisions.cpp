// PbdSimulation's collision stages: the geometry handed to the detector, detection once per
// substep (on the start and the predicted positions), the contacts solved as inequality
// constraints every iteration after the other constraint types, and the pre-stabilization of
// bodies that start below the floor. Restitution is in pbd_contact_response.cpp.
#include "softbody/pbd/pbd_simulation.h"

#include "softbody/collision/boundary_triangles.h"
#include "softbody/collision/contact_terms.h"
#include "softbody/collision/start_overlap.h"
#include "softbody/common/errors.h"
#include "softbody/common/parallel.h"
#include "softbody/common/stepping.h"
#include "softbody/pbd/pbd_plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace softbody
{

void PbdSimulation::setUpCollisions(const std::vector<Tet>& tets,
  const std::vector<std::array<std::int32_t, 3>>& surfaceTriangles)
{
  const std::size_t n = Rest.size();
  for (std::size_t t = 0; t < surfaceTriangles.size(); ++t)
  {
    for (std::int32_t v : surfaceTriangles[t])
    {
      if (v < 0 || static_cast<std::size_t>(v) >= n)
      {
        throw InvalidInputError("Surface triangle " + std::to_string(t) + " refers to point " +
          std::to_string(v) + ", but the input has " + std::to_string(n) + " points.");
      }
    }
  }
  if (!Settings.collisions.on())
  {
    return;
  }
  // Tet bodies collide through their boundary (outward, one-sided), cloth through its own
  // triangles (two-sided), and every other point (voxelized lattices) as a sphere.
  CollisionGeometry geometry;
  geometry.rest = Rest;
  geometry.bodyOf = BodyOf;
  geometry.surfaceTriangles = boundaryTriangles(tets);
  geometry.twoSided.assign(geometry.surfaceTriangles.size(), 0);
  geometry.surfaceTriangles.insert(
    geometry.surfaceTriangles.end(), surfaceTriangles.begin(), surfaceTriangles.end());
  geometry.twoSided.resize(geometry.surfaceTriangles.size(), 1);
  std::vector<char> inTet(n, 0), onSurface(n, 0);
  for (const Tet& t : tets)
  {
    for (std::int32_t v : t)
    {
      inTet[static_cast<std::size_t>(v)] = 1;
    }
  }
  for (const auto& triangle : geometry.surfaceTriangles)
  {
    for (std::int32_t v : triangle)
    {
      onSurface[static_cast<std::size_t>(v)] = 1;
    }
  }
  // Interior points of tet bodies collide too (as in mass-spring), except with self
  // collisions, where an interior point lies behind its own body's one-sided triangles. With
  // only surface vertices held, the floor stopped the bottom surface while the interior
  // points above it fell on through, inverting the bottom tets (an XPBD ellipsoid of 19,019
  // tets resting on the floor: 203 inverted after 0.04 s, 1,129 after 0.2 s).
  const bool interiorCollides = !Settings.collisions.selfCollides();
  geometry.radius.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const bool particle = !inTet[i] && !onSurface[i];
    if (particle)
    {
      geometry.radius[i] = Settings.particleRadius;
    }
    if (particle || onSurface[i] || (interiorCollides && inTet[i]))
    {
      geometry.collidingPoints.push_back(static_cast<std::int32_t>(i));
    }
  }
  // Bodies started inside each other are pushed apart slowly (start_overlap.h): said here,
  // with the depth, so that a slow or entangled start is not a mystery.
  if (Settings.collisions.bodiesCollide() && BodyFirstPoint.size() > 1)
  {
    const std::string overlap = startOverlapWarning(findStartOverlaps(geometry, State.positions));
    if (!overlap.empty())
    {
      Warnings.push_back(overlap);
    }
  }
  Detector = std::make_unique<CollisionDetector>(
    std::move(geometry), Settings.collisions, Settings.floorActive(), Settings.floor);
}

bool PbdSimulation::collisionsActive() const
{
  if (!Detector)
  {
    return false;
  }
  const CollisionSettings& c = Settings.collisions;
  return Settings.floorActive() || HasObstacles || c.selfCollides() ||
    (c.bodiesCollide() && BodyFirstPoint.size() > 1);
}

void PbdSimulation::replan()
{
  Plan = planPbd(Settings, Links, TetElastic, Volumes, Attachments, collisionsActive());
  const std::size_t n = Rest.size();
  if (Plan.runs(Stage::ContactResponse) && State.impactSpeeds.size() != n)
  {
    State.impactSpeeds.assign(n, 0.0);
    State.impactNormals.assign(n, Vec3::Zero());
  }
}

void PbdSimulation::setObstacles(std::vector<ObstacleSurface> obstacles, double endTime)
{
  if (!Detector)
  {
    return; // Collisions Off: nothing is collided with, obstacles included
  }
  const bool had = HasObstacles;
  HasObstacles = !obstacles.empty();
  Detector->setObstacles(std::move(obstacles), endTime);
  // Bodies placed across an obstacle are said to be, once, where the run starts.
  noteObstacleStart(*Detector, State.positions, State.time, ObstacleStartChecked, Warnings);
  if (had != HasObstacles)
  {
    replan();
  }
}

void PbdSimulation::detectContacts(double h)
{
  ScopedStageTimer timer(Plan, Stage::CollisionDetect);
  SubstepStep = h;
  Detector->detect(State.positions, Predicted, SubstepTime, h, Contacts);
  ContactLambda.assign(Contacts.size(), ContactMultipliers{});
  // The set is sorted by point and, per point, obstacle contacts first: each run of one
  // point's obstacle contacts is an independent task; the rest couple several points and are
  // solved in order (Gauss-Seidel), so the result is the same at any thread count.
  ObstacleGroups.clear();
  BodyContacts.clear();
  for (std::size_t k = 0; k < Contacts.size(); ++k)
  {
    if (Contacts[k].kind != ContactKind::Obstacle)
    {
      BodyContacts.push_back(k);
    }
    else if (k == 0 || Contacts[k - 1].point != Contacts[k].point ||
      Contacts[k - 1].kind != ContactKind::Obstacle)
    {
      ObstacleGroups.push_back(k);
    }
  }
  ObstacleGroups.push_back(Contacts.size()); // the end of the last group
  collectHeldTets();
}

void PbdSimulation::projectContacts()
{
  ScopedStageTimer timer(Plan, Stage::SolveContacts);
  const FrictionCoefficients mu{ Settings.collisions.staticFriction, Settings.collisions.dynamicFriction };
  const std::vector<Vec3>& start = State.positions;
  const std::vector<double>& w = InverseMass;
  const double h = SubstepStep;
  const std::size_t groups = ObstacleGroups.size() - 1;
  parallelFor(groups, 256, [&](std::size_t g) {
    for (std::size_t k = ObstacleGroups[g]; k < ObstacleGroups[g + 1]; ++k)
    {
      if (Contacts[k].kind != ContactKind::Obstacle)
      {
        break; // this point's body contacts follow; they are solved below
      }
      const std::size_t i = static_cast<std::size_t>(Contacts[k].point);
      Predicted[i] += projectObstacleContact(Predicted[i], start[i], w[i], Contacts[k], h, mu, ContactLambda[k]).dx[0];
    }
  });
  for (std::size_t k : BodyContacts)
  {
    const Contact& c = Contacts[k];
    const std::size_t p = static_cast<std::size_t>(c.point);
    if (c.kind == ContactKind::PointPoint)
    {
      const std::size_t o = static_cast<std::size_t>(c.other[0]);
      const Projection<2> d = projectPointPointContact(
        { Predicted[p], Predicted[o] }, { start[p], start[o] }, { w[p], w[o] }, c, mu, ContactLambda[k]);
      Predicted[p] += d.dx[0];
      Predicted[o] += d.dx[1];
    }
    else
    {
      const ContactTerms terms = termsOf(c); // point-triangle or edge-edge: four points
      std::array<Vec3, 4> x, x0;
      std::array<double, 4> wk{};
      for (int j = 0; j < 4; ++j)
      {
        const auto i = static_cast<std::size_t>(terms.index[j]);
        x[j] = Predicted[i];
        x0[j] = start[i];
        wk[j] = w[i];
      }
      const Projection<4> d = projectSurfaceContact(x, x0, wk, c, mu, ContactLambda[k]);
      for (int j = 0; j < 4; ++j)
      {
        Predicted[static_cast<std::size_t>(terms.index[j])] += d.dx[j];
      }
    }
  }
}

double PbdSimulation::contactResidual() const
{
  // Only violated contacts count (an inequality that holds asks for nothing), and only those
  // something can move.
  const std::vector<Vec3>& x = Predicted;
  double sum = 0.0;
  for (const Contact& c : Contacts)
  {
    const ContactTerms terms = termsOf(c);
    Vec3 r = c.kind == ContactKind::Obstacle ? Vec3(-c.surfacePoint) : Vec3::Zero();
    double W = 0.0;
    for (int j = 0; j < terms.count; ++j)
    {
      const auto i = static_cast<std::size_t>(terms.index[j]);
      r += terms.coefficient[j] * x[i];
      W += terms.coefficient[j] * terms.coefficient[j] * InverseMass[i];
    }
    // Particles: the distance of the centres, exact rather than linearized.
    const double C = (c.kind == ContactKind::PointPoint ? r.norm() : c.normal.dot(r)) - c.thickness;
    if (C < 0.0 && W > 0.0)
    {
      sum += C * C;
    }
  }
  return sum;
}

void PbdSimulation::liftBodiesOntoFloor()
{
  // Pre-stabilization (Macklin et al. 2014, initial penetration): a correction applied to the
  // positions and to the previous positions alike removes penetration without adding
  // velocity. Here the velocities stay as they are, which is the same thing. Projecting each
  // point onto the floor by itself, as the first step would, flattens the part below it; the
  // elastic constraints then throw the body up (a torus centred on the floor left at 23 m/s).
  // The correction the whole constrained problem converges to for a body in its rest shape is
  // a rigid lift of each body by its deepest penetration, so that is what is applied: by the
  // floor's own contacts, so a lifted body rests exactly at the contact thickness the solve
  // keeps. Bodies with hard pins are held where they are and left to the contact solve.
  // (Obstacles arrive after construction, at the first advance, and are not pre-stabilized:
  // their pushes are not one direction per body.)
  const FloorPlane& floor = Settings.floor;
  const Vec3 n = floor.normal.normalized();
  const std::size_t bodies = BodyFirstPoint.size();
  ContactSet found;
  Detector->detect(State.positions, State.positions, State.time, 0.0, found);
  std::vector<double> deepest(bodies, 0.0);
  for (const Contact& c : found)
  {
    if (c.kind == ContactKind::Obstacle && c.source == -1)
    {
      const std::size_t i = static_cast<std::size_t>(c.point);
      const double C = c.normal.dot(State.positions[i] - c.surfacePoint) - c.thickness;
      const std::int32_t b = BodyOf[i];
      deepest[b] = std::min(deepest[b], C);
    }
  }
  std::vector<char> held(bodies, 0);
  std::size_t below = 0;
  for (std::size_t i = 0; i < Rest.size(); ++i)
  {
    below += n.dot(State.positions[i] - floor.origin) < 0.0 ? 1 : 0;
    if (InverseMass[i] == 0.0)
    {
      held[BodyOf[i]] = 1;
    }
  }
  std::size_t lifted = 0;
  for (std::size_t i = 0; i < Rest.size(); ++i)
  {
    const std::int32_t b = BodyOf[i];
    if (!held[b] && deepest[b] < 0.0)
    {
      State.positions[i] -= deepest[b] * n;
      lifted += BodyFirstPoint[b] == static_cast<std::int32_t>(i) ? 1 : 0;
    }
  }
  if (below == 0)
  {
    return; // within the contact thickness only: lifted onto it, nothing to report
  }
  std::ostringstream message;
  message << below << " points start below the floor: ";
  if (lifted > 0)
  {
    message << lifted << (lifted == 1 ? " body was" : " bodies were")
            << " lifted onto it without velocity";
  }
  if (lifted < bodies && std::any_of(held.begin(), held.end(), [](char h) { return h != 0; }))
  {
    message << (lifted > 0 ? "; " : "") << "pinned bodies stay and are pushed onto it in the first step";
  }
  message << ". Move FloorOrigin below the body to drop it instead.";
  Warnings.push_back(message.str());
}

} // namespace softbody

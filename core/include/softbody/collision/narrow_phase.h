// The exact tests of one candidate pair, shared by every broad phase: a point against a
// triangle (obstacle or body surface), a particle sphere against another, a point against the
// floor plane. Pure functions: positions in, a contact (or none) out.
//
// The query. A contact is reported when the pair, at the end of the substep (the predicted
// positions), is closer than its query radius = thickness + how far either side moved during
// the substep. Any point of the segment start -> predicted lies within its displacement of the
// predicted point, and a moving triangle's points lie within the largest displacement of its
// corners, so a pair that comes within `thickness` at any time of the substep is always
// reported: the sweep is conservative, never missing a contact, at the price of a few
// speculative ones (C > 0, inactive inequalities) for fast points.
//
// One-sidedness. A triangle's free side is the one its normal (b - a) x (c - a) points to
// (flipped by `side` = -1 for two-sided cloth triangles whose point started behind them). In
// front, every feature counts and the normal is the face normal on the face and the direction
// from the closest point on an edge or corner. Behind, only the face counts (a point behind an
// edge of one triangle is in front of, or inside the face of, its neighbour) and only up to one
// query radius deep: a point that crossed the surface during the substep is still caught and
// pushed back out the front, while a point deeper than that is taken to be on the other side
// of a thin wall. So an obstacle (or body part) thinner than the query radius can push points
// through itself: a limit of one-sided surfaces, stated rather than hidden.
#pragma once

#include "softbody/collision/closest_point.h"
#include "softbody/collision/contact.h"

#include <array>
#include <cstdint>

namespace softbody
{

/// A contact before the per-(point, source) reduction of the detector.
struct ContactCandidate
{
  Contact contact;
  double distance = 0.0; ///< |point - closest point| at the predicted positions [m]
  bool onFace = false;   ///< closest feature is the triangle's interior
  /// Behind a triangle's free side (inside a closed surface, or across a cloth triangle): the
  /// point is to leave through this face.
  bool behind = false;
  /// Body triangles (set by the detector): the point was behind this face's plane at the start
  /// of the substep too, a penetration it did not make in this substep.
  bool startedBehind = false;
  /// The touched triangle's vertices (obstacle or body numbering; -1 for the floor and
  /// particles): which contacts lie on neighbouring triangles of one surface.
  std::array<std::int32_t, 3> corners{ -1, -1, -1 };
};

/// Point p against triangle (a, b, c), all at the end of the substep. Fills `out.contact`'s
/// normal, barycentric, surfacePoint (the closest point) and thickness; the caller sets kind,
/// point, other, source and surfaceVelocity. Returns false when out of reach.
bool pointTriangleContact(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double side,
  double thickness, double queryRadius, ContactCandidate& out);

/// Particle sphere against particle sphere: centres p (the contact's point) and q (the other).
/// `fallback` is the direction used when the centres coincide (the start offset, else +z).
bool pointPointContact(const Vec3& p, const Vec3& q, const Vec3& fallback, double thickness,
  double queryRadius, ContactCandidate& out);

/// Point against the floor half-space (x - origin) . normal >= 0: every point below the
/// plane or within the query radius above it (the floor has no back side).
bool pointPlaneContact(const Vec3& p, const Vec3& origin, const Vec3& normal, double thickness,
  double queryRadius, ContactCandidate& out);

/// The ends of two edges, in the order of an EdgeEdge contact: the first edge (a0, a1), the
/// second (b0, b1).
struct EdgePair
{
  Vec3 a0, a1, b0, b1;
};

/// Edge against edge: a contact when the edges' closest points at the end of the substep
/// (`predicted`) lie inside both edges (an end's contact is a point-triangle one, found there)
/// and within the query radius. The normal is the side of the second edge the first was on at
/// the start of the substep (`start`): the common perpendicular of the edges' lines there,
/// pointing from the second toward the first (the offset of the closest points for nearly
/// parallel edges), so edges that crossed during the substep have C < 0 and are pushed back.
/// Edges touching at the start, or parallel, have no such direction and are skipped (their
/// ends' point-triangle contacts hold them). Fills kind-independent fields as
/// pointTriangleContact does (barycentric = (s, t, 0)).
bool edgeEdgeContact(const EdgePair& predicted, const EdgePair& start, double thickness,
  double queryRadius, ContactCandidate& out);

/// The side of a two-sided triangle a point is on: +1 when (p - closest) . normal >= 0, else
/// -1 (evaluated at the start of the substep, where the point has not yet crossed).
double triangleSide(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

} // namespace softbody

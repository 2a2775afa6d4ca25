// Contact kernels of PBD/XPBD: a detected Contact (collision/contact.h) as an inequality
// constraint C >= 0 with Coulomb friction at the position level, and its restitution on the
// velocities. Pure functions: positions, inverse masses and the contact in, corrections out.
//
// Every contact kind is one relative coordinate r = sum_k c_k x_k of its N participants:
//   Obstacle       N = 1: r = x_p                     (c = 1; the surface is not simulated)
//   PointPoint     N = 2: r = x_p - x_o               (c = 1, -1)
//   PointTriangle  N = 4: r = x_p - sum_k b_k x_k     (c = 1, -b_0, -b_1, -b_2)
//   EdgeEdge       N = 4: r = (1-s) x_a0 + s x_a1 - (1-t) x_b0 - t x_b1
// A generalized correction D moves participant k by c_k w_k D, which changes r by W D with
// W = sum_k c_k^2 w_k (so the point and the triangle share the correction by their inverse
// masses and the triangle's corners by their barycentric weights, as in Bridson et al. 2002).
//
// Normal (XPBD with zero compliance, Macklin et al. 2016; applied only while C < 0):
//   dLambda_n = -C / W,  D_n = dLambda_n n,  Lambda_n += dLambda_n
// Friction (Macklin et al. 2014 "Unified Particle Physics", sec. 6.1; Mueller et al. 2020
// "Detailed Rigid Body Simulation with Extended Position Based Dynamics", sec. 3.5): the
// relative tangential displacement over the substep, d_t = [r - r(start) - v_surface h]_t, is
// removed entirely while the accumulated tangential multiplier stays within mu_s Lambda_n
// (static friction); past that the accumulated tangential multiplier is put on the cone of
// mu_k Lambda_n (dynamic friction: the slip is reduced by mu_k times the normal correction).
// Accumulating both multipliers over the iterations of a substep, rather than comparing one
// iteration's corrections, makes the friction bound the whole normal correction of the
// substep: the weight of the layers above a bottom particle reaches it over several
// iterations, and comparing iteration by iteration would give a multi-layer body the friction
// of its bottom layer only (a velocity-level floor friction would need a separate "carried
// push" term for that).
#pragma once

#include "softbody/collision/contact.h"
#include "softbody/collision/contact_terms.h"
#include "softbody/common/geometry.h"
#include "softbody/pbd/pbd_kernels.h" // Projection

#include <algorithm>
#include <array>
#include <cmath>

namespace softbody
{

/// Coulomb coefficients of the contacts (collision_settings.h).
struct FrictionCoefficients
{
  double staticFriction = 0.0;
  double dynamicFriction = 0.0;
};

/// What a contact has accumulated during the iterations of one substep (reset per detection).
struct ContactMultipliers
{
  double normal = 0.0;                    ///< Lambda_n >= 0 [m kg]: sum of dLambda_n
  Vec3 tangential = Vec3::Zero();         ///< accumulated tangential multiplier [m kg]
};

/// The participants of one contact: positions now and at the start of the substep, inverse
/// masses and coefficients c_k (see the file comment).
template <int N>
struct ContactParticipants
{
  std::array<Vec3, N> x;
  std::array<Vec3, N> start;
  std::array<double, N> w{};
  std::array<double, N> c{};
};

namespace detail
{
/// The generalized correction D of one contact given its constraint value C, unit normal n,
/// relative displacement over the substep d (surface motion subtracted) and W > 0.
inline Vec3 contactCorrection(double C, const Vec3& n, const Vec3& d, double W,
  const FrictionCoefficients& mu, ContactMultipliers& lambda)
{
  Vec3 D = Vec3::Zero();
  if (C < 0.0)
  {
    const double dLambda = -C / W;
    lambda.normal += dLambda;
    D += dLambda * n;
  }
  if (lambda.normal <= 0.0 || (mu.staticFriction <= 0.0 && mu.dynamicFriction <= 0.0))
  {
    return D;
  }
  // The normal correction does not change the tangential displacement.
  const Vec3 slip = d - d.dot(n) * n;
  const Vec3 wanted = lambda.tangential - slip / W; // the multiplier that stops all slip
  const double wantedNorm = wanted.norm();
  Vec3 next = wanted;
  if (wantedNorm > mu.staticFriction * lambda.normal)
  {
    // Sliding: the friction multiplier is mu_k Lambda_n along the direction that opposes the
    // slip (never more than what stops it, since then it would stick).
    next = wanted * std::min(1.0, mu.dynamicFriction * lambda.normal / wantedNorm);
  }
  D += next - lambda.tangential;
  lambda.tangential = next;
  return D;
}

template <int N>
Projection<N> applyContactCorrection(double C, const Vec3& n, const Vec3& surfaceDisplacement,
  const ContactParticipants<N>& p, const FrictionCoefficients& mu, ContactMultipliers& lambda)
{
  Projection<N> out;
  double W = 0.0;
  Vec3 d = -surfaceDisplacement;
  for (int k = 0; k < N; ++k)
  {
    W += p.c[k] * p.c[k] * p.w[k];
    d += p.c[k] * (p.x[k] - p.start[k]);
  }
  if (!(W > 0.0))
  {
    return out; // everything involved is pinned
  }
  out.residual = std::min(C, 0.0);
  const double normalBefore = lambda.normal;
  const Vec3 D = contactCorrection(C, n, d, W, mu, lambda);
  out.dLambda = lambda.normal - normalBefore;
  for (int k = 0; k < N; ++k)
  {
    out.dx[k] = (p.c[k] * p.w[k]) * D;
  }
  return out;
}
} // namespace detail

/// Obstacle contact (the floor included): C = n . (x - surfacePoint) - thickness, the surface
/// moving at surfaceVelocity (its displacement over the substep h is subtracted from the slip).
inline Projection<1> projectObstacleContact(const Vec3& x, const Vec3& start, double w,
  const Contact& contact, double h, const FrictionCoefficients& mu, ContactMultipliers& lambda)
{
  const double C = contact.normal.dot(x - contact.surfacePoint) - contact.thickness;
  const ContactParticipants<1> p{ { x }, { start }, { w }, { 1.0 } };
  return detail::applyContactCorrection(C, contact.normal, h * contact.surfaceVelocity, p, mu, lambda);
}

/// Particle against particle: C = |x_p - x_o| - thickness along their current direction (the
/// detected normal where the centres coincide).
inline Projection<2> projectPointPointContact(const std::array<Vec3, 2>& x,
  const std::array<Vec3, 2>& start, const std::array<double, 2>& w, const Contact& contact,
  const FrictionCoefficients& mu, ContactMultipliers& lambda)
{
  const Vec3 r = x[0] - x[1];
  const double distance = r.norm();
  const Vec3 n = distance > 0.0 ? Vec3(r / distance) : contact.normal;
  const ContactParticipants<2> p{ x, start, w, { 1.0, -1.0 } };
  return detail::applyContactCorrection(distance - contact.thickness, n, Vec3::Zero(), p, mu, lambda);
}

/// Point against a body triangle, C = n . (x_p - sum_k b_k x_k) - thickness, or edge against
/// edge, C = n . ((1 - s) x_a0 + s x_a1 - (1 - t) x_b0 - t x_b1) - thickness, with the normal
/// and the weights fixed at detection (x in the order of contact_terms.h: the point and the
/// triangle's corners, or the first edge's ends and the second's).
inline Projection<4> projectSurfaceContact(const std::array<Vec3, 4>& x,
  const std::array<Vec3, 4>& start, const std::array<double, 4>& w, const Contact& contact,
  const FrictionCoefficients& mu, ContactMultipliers& lambda)
{
  const ContactTerms terms = termsOf(contact);
  const ContactParticipants<4> p{ x, start, w, terms.coefficient };
  Vec3 r = Vec3::Zero();
  for (int k = 0; k < 4; ++k)
  {
    r += terms.coefficient[k] * x[k];
  }
  const double C = contact.normal.dot(r) - contact.thickness;
  return detail::applyContactCorrection(C, contact.normal, Vec3::Zero(), p, mu, lambda);
}

/// The obstacle contacts of one tet corner: [begin, end) of the substep's ContactSet (empty when
/// the corner touches nothing).
struct HeldCorner
{
  const Contact* begin = nullptr;
  const Contact* end = nullptr;
};

/// A tet with corners held by obstacle contacts, crushed below `leastVolume`, projected onto the
/// hard inequality V >= leastVolume with every corner kept on the free side of every contact
/// that holds the tet: the component of a corner's volume gradient G_k that points into a
/// holding surface (G_k . n < 0) is removed, and the step moves the corners along those masked
/// gradients G'_k,
///   dx_k = w_k s G'_k,  s = 6 (leastVolume - V) / sum_k w_k G_k . G'_k,
/// which raises the linearized volume by exactly the shortfall (dV = sum_k G_k . dx_k / 6). The
/// held corners cannot be pushed into what holds them, and neither can the others (a corner a
/// hair above the floor is not in the contact set; moving it down would put it through): only
/// what holds the tet can push it, and it pushes away from itself. This is the projection of
/// the volume and the contacts together on their active set; a plain volume projection
/// followed by the contacts, as the iteration otherwise does, lets the contacts flatten the
/// tet again. Returns zero corrections when the tet is not crushed or cannot move that way.
inline std::array<Vec3, 4> uncrushHeldTet(const std::array<Vec3, 4>& x, const std::array<double, 4>& w,
  double leastVolume, const std::array<HeldCorner, 4>& held)
{
  std::array<Vec3, 4> dx{ Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero() };
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  std::array<Vec3, 4> G;
  G[1] = e2.cross(e3);
  G[2] = e3.cross(e1);
  G[3] = e1.cross(e2);
  G[0] = -(G[1] + G[2] + G[3]);
  const double shortfall = leastVolume - e1.dot(G[1]) / 6.0;
  if (!(shortfall > 0.0))
  {
    return dx;
  }
  double denominator = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    Vec3 masked = G[k];
    for (const HeldCorner& corner : held)
    {
      for (const Contact* c = corner.begin; c != corner.end; ++c)
      {
        const double into = masked.dot(c->normal);
        if (into < 0.0)
        {
          masked -= into * c->normal;
        }
      }
    }
    dx[k] = w[k] * masked;
    denominator += G[k].dot(dx[k]);
  }
  if (!(denominator > 0.0))
  {
    return { Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero() };
  }
  const double s = 6.0 * shortfall / denominator;
  for (Vec3& d : dx)
  {
    d *= s;
  }
  return dx;
}

/// Restitution of one contact on the velocities after the solve (Mueller et al. 2020, sec.
/// 3.6): `approach` is the relative normal speed n . (v_rel) before the solve (< 0 when
/// approaching), `now` the one after it. An impact faster than `restingSpeed` leaves at
/// -e approach; a slower one is resting and is not bounced (that would make resting bodies
/// jitter). Returns the change of the relative normal speed (>= 0) to spread over the
/// participants as dv_k = c_k w_k / W times it, along n.
inline double restitutionSpeedChange(double approach, double now, double restitution, double restingSpeed)
{
  if (!(approach < -restingSpeed))
  {
    return 0.0;
  }
  return std::max(0.0, -restitution * approach - now);
}

} // namespace softbody

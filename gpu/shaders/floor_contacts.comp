// Floor contacts, the CPU's operation for operation: CollisionDetector::floorCandidate finds a
// point's contact with the plane (thickness = the collision margin), respondToContacts'
// resolveContact resolves it. The detector's wider candidate query (the point's motion over the
// step and three margins beyond the thickness) is left out: a candidate outside the thickness
// has C >= 0 and no response, and the plane is exact. The response:
// the smallest move onto C = 0, restitution on the approach speed, Coulomb friction on the slip
// with the normal push max(approach change, -C / h), and a sticking point's tangential slip of
// the step undone. The floor is static (no surface velocity) and tet points have no radius.
// One invocation per vertex: the floor's contacts touch one point each.
layout(std430, binding = 0) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 1) readonly buffer StartPositions { dvec4 startPositions[]; };
layout(std430, binding = 2) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 3) buffer Velocities { dvec4 velocities[]; };

uniform dvec3 floorOrigin;
uniform dvec3 floorNormal; ///< unit length, as the detector normalized it
uniform double thickness;
uniform double h;
uniform double staticFriction;
uniform double dynamicFriction;
uniform double restitution;

/// coulombFrictionChange (core: collision/coulomb_friction.h).
dvec3 frictionChange(dvec3 tangential, double normalPush, out bool sticks)
{
  double slipSpeed = norm3(tangential);
  precise double holdable = staticFriction * normalPush;
  sticks = staticFriction > 0.0lf && slipSpeed <= holdable;
  if (sticks)
  {
    return -tangential;
  }
  if (slipSpeed > 0.0lf)
  {
    precise double slowed = dynamicFriction * normalPush / slipSpeed;
    precise dvec3 change = -min(1.0lf, slowed) * tangential;
    return change;
  }
  return dvec3(0.0lf);
}

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  dvec3 p = positions[i].xyz;
  double height = dot3(p - floorOrigin, floorNormal);
  double w = inverseMasses[i];
  if (height > thickness || w <= 0.0lf)
  {
    return; // clear of the floor, or a pinned point (W = 0)
  }
  precise dvec3 surfacePoint = p - height * floorNormal;
  precise dvec3 gap = -surfacePoint + p;
  precise double C = dot3(floorNormal, gap) - thickness;
  if (C >= 0.0lf)
  {
    return;
  }

  // 1. Position: W = w for a single point.
  precise double lambda = -C / w;
  precise dvec3 x = p + (w * lambda) * floorNormal;

  // 2. Velocity: restitution on the approach, friction on the normal push.
  dvec3 v = velocities[i].xyz;
  double normalSpeed = dot3(floorNormal, v);
  precise double normalChange = normalSpeed < 0.0lf ? -(1.0lf + restitution) * normalSpeed : 0.0lf;
  precise double pushOut = -C / h;
  double normalPush = max(normalChange, pushOut);
  bool sticks;
  precise dvec3 tangential = v - normalSpeed * floorNormal;
  precise dvec3 change = normalChange * floorNormal + frictionChange(tangential, normalPush, sticks);
  precise double share = w / w;
  precise dvec3 vNew = v + share * change;
  velocities[i].xyz = vNew;
  if (sticks)
  {
    // Static friction holds the positions too (no creep down a slope).
    precise dvec3 slip = x - startPositions[i].xyz;
    precise dvec3 tangentialSlip = slip - dot3(floorNormal, slip) * floorNormal;
    x = x - share * tangentialSlip;
  }
  positions[i].xyz = x;
}

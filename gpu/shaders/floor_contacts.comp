// Floor (core: resolveFloorContacts). One invocation per vertex: a free point below the plane
// is projected onto it and loses its velocity into the plane (inelastic, frictionless).
layout(std430, binding = 0) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 1) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 2) buffer Velocities { dvec4 velocities[]; };

uniform dvec3 floorOrigin;
uniform dvec3 floorNormal; ///< unit length

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  dvec3 p = positions[i].xyz;
  double depth = dot3(p - floorOrigin, floorNormal);
  if (depth >= 0.0lf || inverseMasses[i] == 0.0lf)
  {
    return;
  }
  precise dvec3 x = p - depth * floorNormal;
  positions[i].xyz = x;
  dvec3 v = velocities[i].xyz;
  double normalSpeed = dot3(v, floorNormal);
  if (normalSpeed < 0.0lf)
  {
    precise dvec3 vNew = v - normalSpeed * floorNormal;
    velocities[i].xyz = vNew;
  }
}

// RK2 midpoint, first half (core: midpoint): the state half a step ahead,
// x_mid = x + (h/2) v, v_mid = v + (h/2) a. One invocation per vertex.
layout(std430, binding = 0) readonly buffer Positions { dvec4 positions[]; };
layout(std430, binding = 1) readonly buffer Velocities { dvec4 velocities[]; };
layout(std430, binding = 2) readonly buffer Accelerations { dvec4 accelerations[]; };
layout(std430, binding = 3) writeonly buffer MidPositions { dvec4 midPositions[]; };
layout(std430, binding = 4) writeonly buffer MidVelocities { dvec4 midVelocities[]; };

uniform double halfH; ///< 0.5 * h, rounded once on the host as core does

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  precise dvec3 x = positions[i].xyz + halfH * velocities[i].xyz;
  precise dvec3 v = velocities[i].xyz + halfH * accelerations[i].xyz;
  midPositions[i] = dvec4(x, 0.0lf);
  midVelocities[i] = dvec4(v, 0.0lf);
}

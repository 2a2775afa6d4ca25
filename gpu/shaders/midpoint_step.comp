// RK2 midpoint, full step with the midpoint rates (core: midpoint):
// x += h v_mid; v += h a(x_mid, v_mid). One invocation per vertex.
layout(std430, binding = 0) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 1) buffer Velocities { dvec4 velocities[]; };
layout(std430, binding = 2) readonly buffer MidVelocities { dvec4 midVelocities[]; };
layout(std430, binding = 3) readonly buffer Accelerations { dvec4 accelerations[]; };

uniform double h;

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  precise dvec3 x = positions[i].xyz + h * midVelocities[i].xyz;
  precise dvec3 v = velocities[i].xyz + h * accelerations[i].xyz;
  positions[i].xyz = x;
  velocities[i].xyz = v;
}

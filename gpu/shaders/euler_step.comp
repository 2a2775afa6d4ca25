// Explicit Euler update (core: explicitEuler): x += h v(t); v += h a(t). One invocation per vertex.
layout(std430, binding = 0) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 1) buffer Velocities { dvec4 velocities[]; };
layout(std430, binding = 2) readonly buffer Accelerations { dvec4 accelerations[]; };

uniform double h;

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  dvec3 v = velocities[i].xyz;
  precise dvec3 x = positions[i].xyz + h * v;
  precise dvec3 vNew = v + h * accelerations[i].xyz;
  positions[i].xyz = x;
  velocities[i].xyz = vNew;
}

// Kick then drift (core: kickDrift): v += kick a; x += h v. Euler-Cromer kicks by h, leapfrog
// Verlet by the mean of the previous and current step (h/2 on the very first step).
layout(std430, binding = 0) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 1) buffer Velocities { dvec4 velocities[]; };
layout(std430, binding = 2) readonly buffer Accelerations { dvec4 accelerations[]; };

uniform double kick;
uniform double h;

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  precise dvec3 v = velocities[i].xyz + kick * accelerations[i].xyz;
  precise dvec3 x = positions[i].xyz + h * v;
  velocities[i].xyz = v;
  positions[i].xyz = x;
}

// The held components of the held points where their conditions put them at the step's end
// (core: BoundaryConditions::holdPoints after the integrator). One invocation per held point;
// the host computes the targets with core's own code (a rigid motion of the rest positions)
// and uploads them when they change.
layout(std430, binding = 0) readonly buffer HeldPoints { int heldPoints[]; };
layout(std430, binding = 1) readonly buffer HeldAxes { uint heldAxes[]; };     // per point
layout(std430, binding = 2) readonly buffer HeldTargets { dvec4 heldTargets[]; }; // x, v per held point
layout(std430, binding = 3) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 4) buffer Velocities { dvec4 velocities[]; };

void main()
{
  uint k = itemIndex();
  if (k >= itemCount)
  {
    return;
  }
  int i = heldPoints[k];
  uint held = heldAxes[i];
  dvec4 x = positions[i], v = velocities[i];
  for (int axis = 0; axis < 3; ++axis)
  {
    if ((held & (1u << uint(axis))) != 0u)
    {
      x[axis] = heldTargets[2u * k].xyz[axis];
      v[axis] = heldTargets[2u * k + 1u].xyz[axis];
    }
  }
  positions[i] = x;
  velocities[i] = v;
}

#version 430 core
// Prepended to every kernel. Doubles are core GLSL since 4.00 (ARB_gpu_shader_fp64), so every
// GL 4.3 context runs them; the arithmetic below mirrors core's Eigen code operation by
// operation (same association order, same guards) so that GPU and CPU agree to rounding.
//
// Layout: per-vertex and per-element vectors are dvec4 with w unused, because std430 gives
// dvec3 arrays a 32-byte stride anyway and dvec4 says so explicitly.

#define WORKGROUP_SIZE 128
layout(local_size_x = WORKGROUP_SIZE) in;

/// Number of items (vertices, edges or tets) this dispatch covers; invocations past it idle.
uniform uint itemCount;

/// Flat item index. Dispatches wider than the 65535 work groups allowed along x wrap into y.
uint itemIndex()
{
  return gl_WorkGroupID.y * gl_NumWorkGroups.x * WORKGROUP_SIZE + gl_GlobalInvocationID.x;
}

// Eigen evaluates these left to right with no fused multiply-add; `precise` forbids the
// compiler from contracting or reassociating them, which keeps results bitwise reproducible.
double dot3(dvec3 a, dvec3 b)
{
  precise double r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

dvec3 cross3(dvec3 a, dvec3 b)
{
  precise dvec3 r = dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return r;
}

double norm3(dvec3 a)
{
  return sqrt(dot3(a, a));
}

/// `a` with the components a point's conditions hold zeroed (core: filterHeld); bit k of
/// `heldAxes` set: component k is held.
dvec3 withoutHeldAxes(dvec3 a, uint heldAxes)
{
  for (int k = 0; k < 3; ++k)
  {
    if ((heldAxes & (1u << uint(k))) != 0u)
    {
      a[k] = 0.0lf;
    }
  }
  return a;
}

// Divergence check (core: maxStretchRatio + the finite-velocity test), reduced per work group.
// Invocation i looks at edge i (l / l0) and at vertex i (is v finite?). Each group writes one
// partial: x = largest finite stretch, y = 1 if some stretch was NaN, z = 1 if some velocity was
// not finite. The host reduces the partials; max and "any" do not depend on order.
layout(std430, binding = 0) readonly buffer Edges { ivec2 edges[]; };
layout(std430, binding = 1) readonly buffer EdgeConstants { dvec4 edgeConstants[]; }; // l0, k, k_d
layout(std430, binding = 2) readonly buffer Positions { dvec4 positions[]; };
layout(std430, binding = 3) readonly buffer Velocities { dvec4 velocities[]; };
layout(std430, binding = 4) writeonly buffer Partials { dvec4 partials[]; };

uniform uint edgeCount;
uniform uint vertexCount;

shared dvec4 groupValues[WORKGROUP_SIZE];

dvec4 combine(dvec4 l, dvec4 r)
{
  return dvec4(max(l.x, r.x), max(l.y, r.y), max(l.z, r.z), 0.0lf);
}

void main()
{
  uint i = itemIndex();
  dvec4 value = dvec4(0.0lf);
  if (i < edgeCount)
  {
    ivec2 edge = edges[i];
    precise double ratio = norm3(positions[edge.x].xyz - positions[edge.y].xyz) / edgeConstants[i].x;
    if (isnan(ratio))
    {
      value.y = 1.0lf;
    }
    else
    {
      value.x = ratio;
    }
  }
  if (i < vertexCount)
  {
    dvec3 v = velocities[i].xyz;
    if (any(isnan(v)) || any(isinf(v)))
    {
      value.z = 1.0lf;
    }
  }
  uint local = gl_LocalInvocationID.x;
  groupValues[local] = value;
  barrier();
  for (uint stride = WORKGROUP_SIZE / 2u; stride > 0u; stride /= 2u)
  {
    if (local < stride)
    {
      groupValues[local] = combine(groupValues[local], groupValues[local + stride]);
    }
    barrier();
  }
  if (local == 0u)
  {
    partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = groupValues[0];
  }
}

// Pass 1, springs (core: springForces in mass_spring_forces.cpp). One invocation per edge:
//   f_a = -(k (l - l0) + k_d n.(v_a - v_b)) n,  n = (p_a - p_b) / l   (f_b = -f_a).
// A zero-length spring has no direction and exerts no force.
layout(std430, binding = 0) readonly buffer Edges { ivec2 edges[]; };
layout(std430, binding = 1) readonly buffer EdgeConstants { dvec4 edgeConstants[]; }; // l0, k, k_d
layout(std430, binding = 2) readonly buffer InPositions { dvec4 inPositions[]; };
layout(std430, binding = 3) readonly buffer InVelocities { dvec4 inVelocities[]; };
layout(std430, binding = 4) writeonly buffer SpringForces { dvec4 springForces[]; };

void main()
{
  uint e = itemIndex();
  if (e >= itemCount)
  {
    return;
  }
  ivec2 edge = edges[e];
  dvec4 c = edgeConstants[e];
  precise dvec3 d = inPositions[edge.x].xyz - inPositions[edge.y].xyz;
  double len = norm3(d);
  if (len < 1e-12lf * c.x)
  {
    springForces[e] = dvec4(0.0lf);
    return;
  }
  precise dvec3 n = d / len;
  precise double stretch = len - c.x;
  double stretchRate = dot3(n, inVelocities[edge.x].xyz - inVelocities[edge.y].xyz);
  precise double magnitude = -(c.y * stretch + c.z * stretchRate);
  springForces[e] = dvec4(magnitude * n, 0.0lf);
}

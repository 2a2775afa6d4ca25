// Strain limiting, pass 1 (core: springCorrections in strain_limit.cpp). One invocation per
// edge: a spring longer than maxStretch * l0 asks for c = (l - maxStretch l0) n / (w_a + w_b),
// end a moving by -w_a c and end b by +w_b c; other springs ask for nothing (c = 0).
// Core stops iterating once no spring is violated; here every iteration runs, which gives the
// same result (a pass with no violated spring moves nothing) without reading a count back.
layout(std430, binding = 0) readonly buffer Edges { ivec2 edges[]; };
layout(std430, binding = 1) readonly buffer EdgeConstants { dvec4 edgeConstants[]; }; // l0, k, k_d
layout(std430, binding = 2) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 3) readonly buffer Positions { dvec4 positions[]; };
layout(std430, binding = 4) writeonly buffer EdgeCorrections { dvec4 edgeCorrections[]; };

uniform double maxStretch;

void main()
{
  uint e = itemIndex();
  if (e >= itemCount)
  {
    return;
  }
  ivec2 edge = edges[e];
  precise dvec3 d = positions[edge.x].xyz - positions[edge.y].xyz;
  double len = norm3(d);
  precise double limit = maxStretch * edgeConstants[e].x;
  precise double wSum = inverseMasses[edge.x] + inverseMasses[edge.y];
  if (len <= limit || wSum == 0.0lf)
  {
    edgeCorrections[e] = dvec4(0.0lf);
    return;
  }
  precise double scale = (len - limit) / (len * wSum);
  edgeCorrections[e] = dvec4(scale * d, 0.0lf);
}

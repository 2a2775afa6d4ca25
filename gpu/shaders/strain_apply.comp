// Strain limiting, pass 2 (core: applyMeanCorrections). One invocation per vertex applies the
// mean of the corrections its violated springs ask for (averaged Jacobi), in CSR order; with
// adjustVelocities (Verlet) the velocity follows: v += dx / h.
layout(std430, binding = 0) readonly buffer VertexEdges { int vertexEdges[]; };
layout(std430, binding = 1) readonly buffer EdgeCorrections { dvec4 edgeCorrections[]; };
layout(std430, binding = 2) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 3) buffer Positions { dvec4 positions[]; };
layout(std430, binding = 4) buffer Velocities { dvec4 velocities[]; };

uniform bool adjustVelocities;
uniform double h;

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  double wi = inverseMasses[i];
  if (wi == 0.0lf)
  {
    return;
  }
  precise dvec3 sum = dvec3(0.0lf);
  int violatedCount = 0;
  int itemsStart = int(itemCount) + 1;
  for (int k = vertexEdges[i]; k < vertexEdges[i + 1]; ++k)
  {
    int item = vertexEdges[itemsStart + k];
    dvec3 c = edgeCorrections[item >= 0 ? item : ~item].xyz;
    if (c == dvec3(0.0lf))
    {
      continue;
    }
    // item >= 0: this vertex is end a and moves by -w_a c; otherwise it is end b: +w_b c.
    sum += item >= 0 ? (-wi) * c : wi * c;
    ++violatedCount;
  }
  if (violatedCount == 0)
  {
    return;
  }
  precise dvec3 delta = sum / double(violatedCount);
  precise dvec3 x = positions[i].xyz + delta;
  positions[i].xyz = x;
  if (adjustVelocities)
  {
    precise dvec3 v = velocities[i].xyz + delta / h;
    velocities[i].xyz = v;
  }
}

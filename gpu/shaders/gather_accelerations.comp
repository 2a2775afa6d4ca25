// Pass 2 (core: computeInternalForces' gather, then MassSpringSimulation::Forces). One
// invocation per vertex sums its own springs and tet corners in CSR order, so no two
// invocations write the same memory and the sum order is fixed: deterministic without atomics.
// Then the conditions' loads are added and a_i = g + w_i f_i for free points, 0 for pinned
// (w_i = 0) ones and along held components.
//
// CSR buffers hold [offsets (vertexCount + 1) | items]. Spring items are the edge index when
// this vertex is the edge's end a, and ~edge (negative) when it is end b, which carries the
// sign of the force without reading the edge.
layout(std430, binding = 0) readonly buffer SpringForces { dvec4 springForces[]; };
layout(std430, binding = 1) readonly buffer VertexEdges { int vertexEdges[]; };
layout(std430, binding = 2) readonly buffer TetScales { double tetScales[]; };
layout(std430, binding = 3) readonly buffer VertexTetCorners { int vertexTetCorners[]; };
layout(std430, binding = 4) readonly buffer Tets { ivec4 tets[]; };
layout(std430, binding = 5) readonly buffer InPositions { dvec4 inPositions[]; };
layout(std430, binding = 6) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 7) writeonly buffer Accelerations { dvec4 accelerations[]; };
layout(std430, binding = 8) readonly buffer Loads { dvec4 loads[]; };     // [N], if hasLoads
layout(std430, binding = 9) readonly buffer HeldAxes { uint heldAxes[]; }; // if hasHeldAxes

uniform bool hasVolumeTerm;
uniform dvec3 gravity;
uniform bool hasLoads;
uniform bool hasHeldAxes;

/// dV/dp of one corner (core: cornerVolumeGradient): a cyclic relabelling keeps the sign.
dvec3 cornerVolumeGradient(ivec4 tet, int corner)
{
  const ivec3 others[4] = ivec3[4](ivec3(1, 3, 2), ivec3(0, 2, 3), ivec3(0, 3, 1), ivec3(0, 1, 2));
  ivec3 o = others[corner];
  dvec3 pj = inPositions[tet[o.x]].xyz;
  dvec3 pk = inPositions[tet[o.y]].xyz;
  dvec3 pl = inPositions[tet[o.z]].xyz;
  precise dvec3 g = cross3(pk - pj, pl - pj) / 6.0lf;
  return g;
}

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  precise dvec3 sum = dvec3(0.0lf);
  int itemsStart = int(itemCount) + 1;
  for (int k = vertexEdges[i]; k < vertexEdges[i + 1]; ++k)
  {
    int item = vertexEdges[itemsStart + k];
    if (item >= 0)
    {
      sum += springForces[item].xyz;
    }
    else
    {
      sum += -springForces[~item].xyz;
    }
  }
  if (hasVolumeTerm)
  {
    for (int k = vertexTetCorners[i]; k < vertexTetCorners[i + 1]; ++k)
    {
      int tetCorner = vertexTetCorners[itemsStart + k];
      int t = tetCorner / 4;
      sum += tetScales[t] * cornerVolumeGradient(tets[t], tetCorner % 4);
    }
  }
  if (hasLoads)
  {
    sum += loads[i].xyz; // core adds the loads to the internal forces
  }
  double w = inverseMasses[i];
  precise dvec3 a = gravity + w * sum;
  dvec3 result = w == 0.0lf ? dvec3(0.0lf) : a;
  accelerations[i] = dvec4(hasHeldAxes ? withoutHeldAxes(result, heldAxes[i]) : result, 0.0lf);
}

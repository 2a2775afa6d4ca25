// Pass 2 for finite-element tets (core: computeTetElasticForces' gather, then
// MassSpringSimulation::Forces). One invocation per vertex sums the forces of its tet corners
// in CSR order (deterministic, no atomics), adds the conditions' loads, then a_i = g + w_i f_i
// for free points, 0 for pinned (w_i = 0) ones and along held components. VertexTetCorners
// holds [offsets (vertexCount + 1) | 4 tet + corner].
layout(std430, binding = 0) readonly buffer CornerForces { dvec4 cornerForces[]; };
layout(std430, binding = 1) readonly buffer VertexTetCorners { int vertexTetCorners[]; };
layout(std430, binding = 2) readonly buffer InverseMasses { double inverseMasses[]; };
layout(std430, binding = 3) writeonly buffer Accelerations { dvec4 accelerations[]; };
layout(std430, binding = 4) readonly buffer Loads { dvec4 loads[]; };     // [N], if hasLoads
layout(std430, binding = 5) readonly buffer HeldAxes { uint heldAxes[]; }; // if hasHeldAxes

uniform dvec3 gravity;
uniform bool hasLoads;
uniform bool hasHeldAxes;

void main()
{
  uint i = itemIndex();
  if (i >= itemCount)
  {
    return;
  }
  precise dvec3 sum = dvec3(0.0lf);
  int itemsStart = int(itemCount) + 1;
  for (int k = vertexTetCorners[i]; k < vertexTetCorners[i + 1]; ++k)
  {
    sum += cornerForces[vertexTetCorners[itemsStart + k]].xyz;
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

// Pass 1, volumes (core: volumeForceScales). One invocation per tet:
//   s = -(k' (V - V0) + k_d' dV/dt),  dV/dt = sum_k g_k . v_k,  g_k = dV/dp_k;
// the force on corner k is s g_k (applied by the gather pass).
layout(std430, binding = 0) readonly buffer Tets { ivec4 tets[]; };
layout(std430, binding = 1) readonly buffer TetConstants { dvec4 tetConstants[]; }; // V0, k', k_d'
layout(std430, binding = 2) readonly buffer InPositions { dvec4 inPositions[]; };
layout(std430, binding = 3) readonly buffer InVelocities { dvec4 inVelocities[]; };
layout(std430, binding = 4) writeonly buffer TetScales { double tetScales[]; };

void main()
{
  uint t = itemIndex();
  if (t >= itemCount)
  {
    return;
  }
  ivec4 tet = tets[t];
  dvec3 p0 = inPositions[tet.x].xyz, p1 = inPositions[tet.y].xyz;
  dvec3 p2 = inPositions[tet.z].xyz, p3 = inPositions[tet.w].xyz;
  // tetVolumeGradients (geometry.h)
  precise dvec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p3 - p0;
  precise dvec3 g1 = cross3(e2, e3) / 6.0lf;
  precise dvec3 g2 = cross3(e3, e1) / 6.0lf;
  precise dvec3 g3 = cross3(e1, e2) / 6.0lf;
  precise dvec3 g0 = -((g1 + g2) + g3);
  // signedTetVolume (geometry.h)
  precise double volume = dot3(p1 - p0, cross3(p2 - p0, p3 - p0)) / 6.0lf;
  precise double volumeRate = 0.0lf;
  volumeRate += dot3(g0, inVelocities[tet.x].xyz);
  volumeRate += dot3(g1, inVelocities[tet.y].xyz);
  volumeRate += dot3(g2, inVelocities[tet.z].xyz);
  volumeRate += dot3(g3, inVelocities[tet.w].xyz);
  dvec4 c = tetConstants[t];
  precise double s = -(c.y * (volume - c.x) + c.z * volumeRate);
  tetScales[t] = s;
}

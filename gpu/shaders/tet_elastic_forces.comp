// Pass 1, finite-element tets (core: tet_elastic_forces.cpp's cornerForces with the law's
// stress and viscousStress). One invocation per tet:
//   F = sum_c x_c g_c^T,  Fdot = sum_c v_c g_c^T,  D = sym(F^T Fdot),
//   Stable Neo-Hookean: P = mu (1 - 1 / (I_C + 1)) F + lambda (J - alpha) cof(F)
//   Corotated:          P = 2 mu (F - R) + lambda (J - 1) cof(F),  R = U V^T
//   P += beta F (2 mu_lin D + lambda_lin tr(D) I),
//   f_c = -V0 P g_c   (the corner forces, summed per point by the gather pass).
// Corotated's P is core's U diag(dPsi/ds) V^T written without its SVD's bases: U diag(s) V^T
// = F and U diag(s1 s2, s0 s2, s0 s1) V^T = cof(F) for proper U and V, so only the rotation R
// is needed. It comes from a one-sided Jacobi SVD (below) rather than core's closed form:
// GLSL has no double-precision trigonometry for Eigen's direct eigensolver, and Jacobi needs
// only sqrt. Both give F's rotation to rounding, so Corotated agrees with the CPU to rounding,
// not bit for bit.
// Stable Neo-Hookean's matrices are written out entry by entry, each sum in the order Eigen's
// SSE2 code (two doubles per packet, core's x86-64 build) adds it, so that the CPU's rounding
// is reproduced: a 3x3 product or matrix-vector product sums rows 0 and 1 (one packet) as
// (p0 + p1) + p2 and row 2 (the scalar tail) as p0 + (p1 + p2); a trace is d0 + (d1 + d2);
// |F|^2 adds two lanes of F's entries in memory order. A build of core with wider packets
// (AVX) would sum otherwise.
layout(std430, binding = 0) readonly buffer Tets { ivec4 tets[]; };
layout(std430, binding = 1) readonly buffer ShapeGradients { dvec4 shapeGradients[]; }; // 4 per tet
layout(std430, binding = 2) readonly buffer TetLaws { dvec4 tetLaws[]; }; // 2 per tet, below
layout(std430, binding = 3) readonly buffer InPositions { dvec4 inPositions[]; };
layout(std430, binding = 4) readonly buffer InVelocities { dvec4 inVelocities[]; };
layout(std430, binding = 5) writeonly buffer CornerForces { dvec4 cornerForces[]; }; // 4 per tet

/// Corotated instead of Stable Neo-Hookean (one model per body).
uniform bool corotated;

// tetLaws[2 t]     = (V0, law mu, law lambda, alpha; unused by Corotated)
// tetLaws[2 t + 1] = (linear mu, linear lambda, beta (damping time), 0)

/// sum_c y_c g_c^T over the tet's corners (core: deformationGradient).
dmat3 gradientOf(ivec4 tet, uint t, bool ofVelocities)
{
  dmat3 f = dmat3(0.0lf);
  for (int c = 0; c < 4; ++c)
  {
    dvec3 y = ofVelocities ? inVelocities[tet[c]].xyz : inPositions[tet[c]].xyz;
    dvec3 g = shapeGradients[4 * t + uint(c)].xyz;
    for (int col = 0; col < 3; ++col)
    {
      for (int row = 0; row < 3; ++row)
      {
        precise double term = y[row] * g[col];
        if (c == 0)
        {
          f[col][row] = term;
        }
        else
        {
          precise double sum = f[col][row] + term;
          f[col][row] = sum;
        }
      }
    }
  }
  return f;
}

/// a^T b, entry (i, j) = sum_k a(k, i) b(k, j).
dmat3 transposeTimes(dmat3 a, dmat3 b)
{
  dmat3 r;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      precise double s = a[i][0] * b[j][0] + a[i][1] * b[j][1] + a[i][2] * b[j][2];
      r[j][i] = s;
    }
  }
  return r;
}

/// p0 + p1 + p2 in the order Eigen's column-major product sums row `row` (see above).
double rowSum(int row, double p0, double p1, double p2)
{
  precise double packetRows = (p0 + p1) + p2;
  precise double tailRow = p0 + (p1 + p2);
  return row < 2 ? packetRows : tailRow;
}

/// a b, entry (i, j) = sum_k a(i, k) b(k, j).
dmat3 times(dmat3 a, dmat3 b)
{
  dmat3 r;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      precise double p0 = a[0][i] * b[j][0];
      precise double p1 = a[1][i] * b[j][1];
      precise double p2 = a[2][i] * b[j][2];
      r[j][i] = rowSum(i, p0, p1, p2);
    }
  }
  return r;
}

/// F's rotation-variant rotation R = U V^T (core: rotationVariantSvd): U and V proper
/// rotations, the singular values sorted by magnitude with only the last one negative for an
/// inverted F. One-sided (Hestenes) Jacobi: plane rotations of F V's columns until each pair is
/// orthogonal, V accumulating them; the columns' norms are then the singular values to full
/// relative accuracy, flat tets included.
dmat3 rotationOf(dmat3 f)
{
  dmat3 a = f;
  dmat3 v = dmat3(1.0lf);
  const ivec2 pairs[3] = ivec2[3](ivec2(0, 1), ivec2(0, 2), ivec2(1, 2));
  for (int sweep = 0; sweep < 12; ++sweep) // converges quadratically: 3-5 sweeps in practice
  {
    bool orthogonal = true;
    for (int k = 0; k < 3; ++k)
    {
      int p = pairs[k].x, q = pairs[k].y;
      double alpha = dot3(a[p], a[p]), beta = dot3(a[q], a[q]), gamma = dot3(a[p], a[q]);
      if (!(abs(gamma) > 1.0e-15lf * sqrt(alpha) * sqrt(beta)))
      {
        continue;
      }
      orthogonal = false;
      // The smaller root of t^2 + 2 zeta t - 1 = 0 (the rotation by at most 45 degrees).
      precise double zeta = (beta - alpha) / (2.0lf * gamma);
      precise double t = (zeta >= 0.0lf ? 1.0lf : -1.0lf) / (abs(zeta) + sqrt(1.0lf + zeta * zeta));
      precise double c = 1.0lf / sqrt(1.0lf + t * t);
      precise double s = c * t;
      precise dvec3 ap = c * a[p] - s * a[q], aq = s * a[p] + c * a[q];
      precise dvec3 vp = c * v[p] - s * v[q], vq = s * v[p] + c * v[q];
      a[p] = ap;
      a[q] = aq;
      v[p] = vp;
      v[q] = vq;
    }
    if (orthogonal)
    {
      break;
    }
  }
  // Sort the columns by their norms, largest first.
  dvec3 n = dvec3(dot3(a[0], a[0]), dot3(a[1], a[1]), dot3(a[2], a[2]));
  for (int pass = 0; pass < 2; ++pass)
  {
    for (int k = 0; k < 2 - pass; ++k)
    {
      if (n[k] < n[k + 1])
      {
        dvec3 column = a[k];
        a[k] = a[k + 1];
        a[k + 1] = column;
        column = v[k];
        v[k] = v[k + 1];
        v[k + 1] = column;
        double norm = n[k];
        n[k] = n[k + 1];
        n[k + 1] = norm;
      }
    }
  }
  if (dot3(v[0], cross3(v[1], v[2])) < 0.0lf)
  {
    v[2] = -v[2]; // a proper V; F V's last column follows
    a[2] = -a[2];
  }
  // U's first two columns from F V's, made orthonormal; the third their cross product, so U is
  // proper and an inverted F's last singular value comes out negative.
  dmat3 u;
  double s0 = norm3(a[0]);
  u[0] = s0 > 0.0lf ? a[0] / s0 : v[0];
  precise dvec3 b = a[1] - dot3(u[0], a[1]) * u[0];
  double s1 = norm3(b);
  if (s1 > 1.0e-12lf * s0)
  {
    u[1] = b / s1;
  }
  else
  {
    // A flat F: its second direction is free; any unit vector normal to u0 serves.
    dvec3 axis = abs(u[0].x) < 0.9lf ? dvec3(1.0lf, 0.0lf, 0.0lf) : dvec3(0.0lf, 1.0lf, 0.0lf);
    dvec3 normal = cross3(u[0], axis);
    u[1] = normal / norm3(normal);
  }
  u[2] = cross3(u[0], u[1]);
  return u * transpose(v);
}

void main()
{
  uint t = itemIndex();
  if (t >= itemCount)
  {
    return;
  }
  ivec4 tet = tets[t];
  dvec4 law = tetLaws[2 * t];
  dvec4 linear = tetLaws[2 * t + 1];
  double mu = law.y, lambda = law.z, alpha = law.w;
  dmat3 f = gradientOf(tet, t, false);

  dmat3 cofactor;
  cofactor[0] = cross3(f[1], f[2]);
  cofactor[1] = cross3(f[2], f[0]);
  cofactor[2] = cross3(f[0], f[1]);
  double j = dot3(f[0], cofactor[0]);
  dmat3 stress;
  if (corotated)
  {
    dmat3 r = rotationOf(f);
    precise double twoMu = 2.0lf * mu;
    precise double volumetric = lambda * (j - 1.0lf);
    for (int col = 0; col < 3; ++col)
    {
      precise dvec3 column = twoMu * (f[col] - r[col]) + volumetric * cofactor[col];
      stress[col] = column;
    }
  }
  else
  {
    // StableNeoHookeanLaw::energyAndStressOf
    double e[9];
    for (int k = 0; k < 9; ++k)
    {
      precise double square = f[k / 3][k % 3] * f[k / 3][k % 3];
      e[k] = square;
    }
    precise double ic = (((e[0] + e[2]) + (e[4] + e[6])) + ((e[1] + e[3]) + (e[5] + e[7]))) + e[8];
    precise double shear = mu * (1.0lf - 1.0lf / (ic + 1.0lf));
    precise double volumetric = lambda * (j - alpha);
    for (int col = 0; col < 3; ++col)
    {
      precise dvec3 column = shear * f[col] + volumetric * cofactor[col];
      stress[col] = column;
    }
  }

  double beta = linear.z;
  if (beta > 0.0lf)
  {
    // viscousStress(F, Fdot, linear, beta): beta F (2 mu D + lambda tr(D) I).
    dmat3 local = transposeTimes(f, gradientOf(tet, t, true));
    dmat3 d;
    for (int col = 0; col < 3; ++col)
    {
      for (int row = 0; row < 3; ++row)
      {
        precise double s = 0.5lf * (local[col][row] + local[row][col]);
        d[col][row] = s;
      }
    }
    precise double trace = d[0][0] + (d[1][1] + d[2][2]);
    precise double twoMu = 2.0lf * linear.x;
    precise double lambdaTrace = linear.y * trace;
    dmat3 inner;
    for (int col = 0; col < 3; ++col)
    {
      for (int row = 0; row < 3; ++row)
      {
        precise double s = twoMu * d[col][row] + lambdaTrace * (row == col ? 1.0lf : 0.0lf);
        inner[col][row] = s;
      }
    }
    dmat3 scaledF;
    for (int col = 0; col < 3; ++col)
    {
      precise dvec3 column = beta * f[col];
      scaledF[col] = column;
    }
    dmat3 viscous = times(scaledF, inner);
    for (int col = 0; col < 3; ++col)
    {
      precise dvec3 column = stress[col] + viscous[col];
      stress[col] = column;
    }
  }

  // f_c = (-V0 P) g_c
  double minusV0 = -law.x;
  for (int c = 0; c < 4; ++c)
  {
    dvec3 g = shapeGradients[4 * t + uint(c)].xyz;
    dvec3 force;
    for (int row = 0; row < 3; ++row)
    {
      precise double p0 = (minusV0 * stress[0][row]) * g.x;
      precise double p1 = (minusV0 * stress[1][row]) * g.y;
      precise double p2 = (minusV0 * stress[2][row]) * g.z;
      force[row] = rowSum(row, p0, p1, p2);
    }
    cornerForces[4 * t + uint(c)] = dvec4(force, 0.0lf);
  }
}

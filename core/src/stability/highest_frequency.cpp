#include "softbody/stability/highest_frequency.h"

#include "softbody/common/geometry.h"
#include "softbody/common/parallel.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace softbody
{
namespace
{

constexpr std::size_t kGrain = 2048;

/// The rest stiffness as a matrix-free operator on the mass-scaled form A = D K D, D = M^-1/2:
/// y = A x in three passes, each over independent work (springs, tets, then a gather per vertex
/// in CSR order), so the product is the same bit for bit at any thread count.
class ScaledRestStiffness
{
public:
  ScaledRestStiffness(const Topology& topology, const ElementConstants& constants,
    const std::vector<double>& inverseMass, const std::vector<Vec3>& rest)
    : Topology_(topology)
    , Constants_(constants)
    , Scale(topology.vertexCount)
    , Direction(topology.edges.size())
    , Gradient(constants.hasVolumeTerm ? topology.tets.size() : 0)
    , SpringScalar(topology.edges.size())
    , TetScalar(Gradient.size())
    , Scaled(topology.vertexCount)
  {
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) { Scale[i] = std::sqrt(inverseMass[i]); });
    parallelFor(topology.edges.size(), kGrain, [&](std::size_t e) {
      const Vec3 d = rest[topology.edges[e].a] - rest[topology.edges[e].b];
      const double length = d.norm();
      Direction[e] = length > 0.0 ? Vec3(d / length) : Vec3::Zero(); // no direction: no stiffness
    });
    parallelFor(Gradient.size(), kGrain, [&](std::size_t t) {
      const Tet& tet = topology.tets[t];
      Gradient[t] = tetVolumeGradients(rest[tet[0]], rest[tet[1]], rest[tet[2]], rest[tet[3]]);
    });
  }

  void apply(const std::vector<Vec3>& x, std::vector<Vec3>& y)
  {
    const Topology& topology = Topology_;
    const ElementConstants& c = Constants_;
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) { Scaled[i] = Scale[i] * x[i]; });
    // Spring e: the block k n n^T acting on (u_a - u_b); its force scalar k n.(u_a - u_b).
    parallelFor(topology.edges.size(), kGrain, [&](std::size_t e) {
      const Edge& edge = topology.edges[e];
      SpringScalar[e] = c.springStiffness[e] * Direction[e].dot(Scaled[edge.a] - Scaled[edge.b]);
    });
    // Tet t: k' g (g . u), the Hessian of k'/2 (V - V0)^2 at V = V0.
    parallelFor(Gradient.size(), kGrain, [&](std::size_t t) {
      const Tet& tet = topology.tets[t];
      double rate = 0.0;
      for (int k = 0; k < 4; ++k)
      {
        rate += Gradient[t][k].dot(Scaled[tet[k]]);
      }
      TetScalar[t] = c.volumeStiffness[t] * rate;
    });
    y.resize(topology.vertexCount);
    parallelFor(topology.vertexCount, kGrain, [&](std::size_t i) {
      Vec3 sum = Vec3::Zero();
      const Csr& edges = topology.vertexEdges;
      for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
      {
        const std::int32_t e = edges.items[k];
        const double s = topology.edges[e].a == static_cast<std::int32_t>(i) ? SpringScalar[e] : -SpringScalar[e];
        sum += s * Direction[e];
      }
      if (!Gradient.empty())
      {
        const Csr& corners = topology.vertexTetCorners;
        for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
        {
          const std::int32_t corner = corners.items[k];
          sum += TetScalar[corner / 4] * Gradient[corner / 4][corner % 4];
        }
      }
      y[i] = Scale[i] * sum;
    });
  }

private:
  const Topology& Topology_;
  const ElementConstants& Constants_;
  std::vector<double> Scale;                   ///< sqrt(w_i), 0 for pinned points
  std::vector<Vec3> Direction;                 ///< rest unit direction of each spring, a - b
  std::vector<std::array<Vec3, 4>> Gradient;   ///< rest volume gradients per tet
  std::vector<double> SpringScalar, TetScalar; ///< scratch of the element pass
  std::vector<Vec3> Scaled;                    ///< scratch: D x
};

double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
  return parallelSum(a.size(), [&](std::size_t i) { return a[i].dot(b[i]); });
}

/// SplitMix64's finalizer: a well-mixed 64-bit hash.
std::uint64_t mix(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Start vector entry of one point: pseudo-random in [-1, 1)^3, hashed from the bits of the
/// point's rest position rather than its index, so a renumbered mesh (core's cache reordering)
/// gets the same start vector and the same step. A smooth start would be nearly orthogonal to the
/// top modes, which alternate from point to point.
Vec3 hashedStart(const Vec3& p)
{
  std::uint64_t h = 0x9E3779B97F4A7C15ull;
  for (int k = 0; k < 3; ++k)
  {
    h = mix(h ^ std::bit_cast<std::uint64_t>(p[k]));
  }
  Vec3 v;
  for (int k = 0; k < 3; ++k)
  {
    h = mix(h + 0x9E3779B97F4A7C15ull);
    v[k] = double(h >> 11) * 0x1.0p-52 - 1.0;
  }
  return v;
}

} // namespace

double gershgorinFrequencyBound(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions)
{
  // Per tet: |g_j| of each corner at rest and their sum, for the volume block norms.
  std::vector<double> gradientNormSum(topology.tets.size(), 0.0);
  std::vector<std::array<double, 4>> gradientNorm(topology.tets.size());
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    const Tet& tet = topology.tets[t];
    const auto g = tetVolumeGradients(
      restPositions[tet[0]], restPositions[tet[1]], restPositions[tet[2]], restPositions[tet[3]]);
    for (int k = 0; k < 4; ++k)
    {
      gradientNorm[t][k] = g[k].norm();
      gradientNormSum[t] += gradientNorm[t][k];
    }
  }

  double maxOmegaSquared = 0.0;
  for (std::size_t i = 0; i < topology.vertexCount; ++i)
  {
    if (inverseMass[i] == 0.0)
    {
      continue;
    }
    // Row i of K: diagonal block sum_e k n n^T (norm <= sum k) plus off-diagonal blocks k n n^T
    // (norm k each); a tet adds k' g_i g_j^T blocks of norm k' |g_i| |g_j|.
    double rowNorm = 0.0;
    const Csr& edges = topology.vertexEdges;
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      rowNorm += 2.0 * constants.springStiffness[edges.items[k]];
    }
    const Csr& corners = topology.vertexTetCorners;
    for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
    {
      const std::int32_t t = corners.items[k] / 4;
      rowNorm += constants.volumeStiffness[t] * gradientNorm[t][corners.items[k] % 4] *
        gradientNormSum[t];
    }
    maxOmegaSquared = std::max(maxOmegaSquared, inverseMass[i] * rowNorm);
  }
  return std::sqrt(maxOmegaSquared);
}

LanczosFrequency lanczosFrequencyEstimate(const Topology& topology,
  const ElementConstants& constants, const std::vector<double>& inverseMass,
  const std::vector<Vec3>& restPositions, int iterations)
{
  if (topology.vertexCount == 0 || iterations < 1)
  {
    return {};
  }
  ScaledRestStiffness stiffness(topology, constants, inverseMass, restPositions);
  return lanczosFrequencyEstimate(
    [&](const std::vector<Vec3>& x, std::vector<Vec3>& y) { stiffness.apply(x, y); }, inverseMass, restPositions,
    iterations);
}

LanczosFrequency lanczosFrequencyEstimate(const ScaledRestProduct& product,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions, int iterations)
{
  LanczosFrequency result;
  const std::size_t n = restPositions.size();
  if (n == 0 || iterations < 1)
  {
    return result;
  }

  // Plain Lanczos (three-term recurrence, no reorthogonalization: its loss of orthogonality
  // only repeats converged Ritz values, it does not move the top one past lambda_max).
  std::vector<Vec3> q(n), previous(n, Vec3::Zero()), w(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double free = inverseMass[i] > 0.0 ? 1.0 : 0.0; // pinned points have no modes
    q[i] = free * hashedStart(restPositions[i]);
  }
  const double startNorm = std::sqrt(dot(q, q));
  if (!(startNorm > 0.0))
  {
    return result; // every point pinned: no free mode
  }
  parallelFor(n, kGrain, [&](std::size_t i) { q[i] /= startNorm; });

  std::vector<double> alpha, beta; // T's diagonal and the norms beta_1..beta_m
  double scaleOfT = 0.0;
  for (int j = 0; j < iterations; ++j)
  {
    product(q, w);
    const double a = dot(q, w);
    const double b0 = beta.empty() ? 0.0 : beta.back();
    parallelFor(n, kGrain, [&](std::size_t i) { w[i] -= a * q[i] + b0 * previous[i]; });
    const double b = std::sqrt(dot(w, w));
    alpha.push_back(a);
    beta.push_back(b);
    scaleOfT = std::max({ scaleOfT, std::abs(a), b });
    if (!(b > 1e-13 * scaleOfT))
    {
      break; // an invariant subspace: T's eigenvalues are exact eigenvalues of A
    }
    parallelFor(n, kGrain, [&](std::size_t i) {
      previous[i] = q[i];
      q[i] = w[i] / b;
    });
  }
  const int m = static_cast<int>(alpha.size());
  result.iterations = m;

  Eigen::VectorXd diagonal(m), offDiagonal(std::max(m - 1, 0));
  for (int k = 0; k < m; ++k)
  {
    diagonal[k] = alpha[k];
    if (k + 1 < m)
    {
      offDiagonal[k] = beta[k];
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal;
  tridiagonal.computeFromTridiagonal(diagonal, offDiagonal, Eigen::ComputeEigenvectors);
  if (tridiagonal.info() != Eigen::Success)
  {
    // Eigen's implicit QR gives up after 30 m sweeps; seen only with hundreds of steps, where the
    // lost orthogonality repeats converged values many times. No estimate: the caller falls back.
    return result;
  }
  const double theta = tridiagonal.eigenvalues()[m - 1]; // ascending
  // Residual of the top Ritz pair: ||A y - theta y|| = beta_m |s_m| (s: T's eigenvector).
  const double residual = beta[m - 1] * std::abs(tridiagonal.eigenvectors()(m - 1, m - 1));
  result.ritzOmega = std::sqrt(std::max(theta, 0.0));
  result.upperOmega = std::sqrt(std::max(theta + residual, 0.0));
  return result;
}

double highestFrequencyBound(const Topology& topology, const ElementConstants& constants,
  const std::vector<double>& inverseMass, const std::vector<Vec3>& restPositions)
{
  const double gershgorin = gershgorinFrequencyBound(topology, constants, inverseMass, restPositions);
  const LanczosFrequency lanczos = lanczosFrequencyEstimate(
    topology, constants, inverseMass, restPositions, kFrequencyLanczosSteps);
  return lanczos.upperOmega > 0.0 ? std::min(gershgorin, kDeformationMargin * lanczos.upperOmega)
                                  : gershgorin;
}

} // namespace softbody

#include "softbody/massspring/mass_spring_forces.h"

#include "softbody/common/parallel.h"
#include "softbody/common/simd.h"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic ignored "-Wpsabi" // 32-byte vectors passed between inlined helpers only
#endif

namespace softbody
{
namespace
{

// Element passes run in chunks of whole lane blocks; the gather keeps TBB's grain.
constexpr std::size_t kElementChunk = 2048;
constexpr std::size_t kVertexGrain = 1024;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are read as packed xyz triples");
static_assert(sizeof(Edge) == 2 * sizeof(std::int32_t), "an edge's ends are read as an index pair");

/// Offsets of four consecutive xyz triples (a contiguous transposed store).
constexpr std::int32_t kConsecutive[4] = { 0, 1, 2, 3 };
/// Offsets of corner k of four consecutive tets in the 4 t + k corner layout.
constexpr std::int32_t kEveryFourth[4] = { 0, 4, 8, 12 };

/// Pass 1, springs, for one lane (T = double) or four (T = simd::Lanes4): force on end a,
///   f_a = -(k (l - l0) + k_d n.(v_a - v_b)) n,  n = (p_a - p_b) / l   (f_b = -f_a).
/// A zero-length spring has no direction; it exerts no force (guarded, never NaN).
/// The operations and their order are the ones the GPU shaders (gpu/shaders/spring_forces.comp)
/// repeat bit for bit. The divisions are not folded (two instead of four per spring, three
/// instead of 22 per tet): that would break this parity, and this pass is bound by memory
/// traffic more than by division (README, Performance, "Wide kernels").
template <class T>
SOFTBODY_SIMD_INLINE void springBlock(const Topology& topology, const ElementConstants& c, std::size_t e,
  const double* x, const double* v, double* out)
{
  using simd::broadcast;
  const std::int32_t* ends = &topology.edges[e].a;
  const simd::Vec3Lanes<T> d = simd::gather3<T>(x, ends, 2) - simd::gather3<T>(x, ends + 1, 2);
  const T rest = simd::load<T>(&c.restLength[e]);
  const T length = simd::sqrt(simd::dot(d, d));
  const auto hasDirection = simd::negate(length < broadcast<T>(1e-12) * rest);
  const simd::Vec3Lanes<T> n = { d.x / length, d.y / length, d.z / length };
  const T stretch = length - rest;
  const T stretchRate = simd::dot(n, simd::gather3<T>(v, ends, 2) - simd::gather3<T>(v, ends + 1, 2));
  const T magnitude = -(simd::load<T>(&c.springStiffness[e]) * stretch + simd::load<T>(&c.springDamping[e]) * stretchRate);
  const T zero = broadcast<T>(0.0);
  const simd::Vec3Lanes<T> f = magnitude * n;
  simd::scatter3<T>(out + 3 * e, kConsecutive, 1,
    { simd::select(hasDirection, f.x, zero), simd::select(hasDirection, f.y, zero), simd::select(hasDirection, f.z, zero) },
    0xfu);
}

/// Pass 1, volumes: f_k = s dV/dp_k with s = -(k' (V - V0) + k_d' dV/dt), dV/dt = sum g_j.v_j,
/// written per corner (4 t + k), with the operations of the GPU's volume_forces.comp and its
/// gather: g_k = (e_i x e_j) / 6 from tetVolumeGradients,
/// corner 0's force from its own cyclic cross product (p3 - p1) x (p2 - p1) / 6 as the GPU's
/// gather computes it, so CPU and GPU stay bitwise equal.
template <class T>
SOFTBODY_SIMD_INLINE void volumeBlock(const Topology& topology, const ElementConstants& c, std::size_t t,
  const double* x, const double* v, double* out)
{
  using simd::broadcast;
  const std::int32_t* corners = topology.tets[t].data();
  const simd::Vec3Lanes<T> p0 = simd::gather3<T>(x, corners, 4);
  const simd::Vec3Lanes<T> p1 = simd::gather3<T>(x, corners + 1, 4);
  const simd::Vec3Lanes<T> p2 = simd::gather3<T>(x, corners + 2, 4);
  const simd::Vec3Lanes<T> p3 = simd::gather3<T>(x, corners + 3, 4);
  const simd::Vec3Lanes<T> e1 = p1 - p0, e2 = p2 - p0, e3 = p3 - p0;
  const T six = broadcast<T>(6.0);
  auto overSix = [six](const simd::Vec3Lanes<T>& a) { return simd::Vec3Lanes<T>{ a.x / six, a.y / six, a.z / six }; };
  const simd::Vec3Lanes<T> cross1 = simd::cross(e2, e3);
  simd::Vec3Lanes<T> g[4];
  g[1] = overSix(cross1);
  g[2] = overSix(simd::cross(e3, e1));
  g[3] = overSix(simd::cross(e1, e2));
  g[0] = -((g[1] + g[2]) + g[3]);
  const T volume = simd::dot(e1, cross1) / six;
  T volumeRate = broadcast<T>(0.0);
  for (int k = 0; k < 4; ++k)
  {
    volumeRate = volumeRate + simd::dot(g[k], simd::gather3<T>(v, corners + k, 4));
  }
  const T scale = -(simd::load<T>(&c.volumeStiffness[t]) * (volume - simd::load<T>(&c.restVolume[t])) +
                    simd::load<T>(&c.volumeDamping[t]) * volumeRate);
  g[0] = overSix(simd::cross(p3 - p1, p2 - p1));
  for (int k = 0; k < 4; ++k)
  {
    simd::scatter3<T>(out + 3 * (4 * t + static_cast<std::size_t>(k)), kEveryFourth, 1, scale * g[k], 0xfu);
  }
}

/// Elements [begin, end): blocks of `Lanes` (double: one element at a time), then the rest one at
/// a time. Inlined into one wrapper per SimdLevel, which compiles it for that level
/// (common/simd.h); the baseline runs one lane, as in pbd_wide_kernels.cpp.
template <class Lanes, bool Springs>
SOFTBODY_SIMD_INLINE void elementRange(const Topology& topology, const ElementConstants& c, std::size_t begin,
  std::size_t end, const double* x, const double* v, double* out)
{
  std::size_t i = begin;
  if constexpr (!std::is_same_v<Lanes, double>)
  {
    for (; i + simd::kWidth <= end; i += simd::kWidth)
    {
      if constexpr (Springs)
      {
        springBlock<Lanes>(topology, c, i, x, v, out);
      }
      else
      {
        volumeBlock<Lanes>(topology, c, i, x, v, out);
      }
    }
  }
  for (; i < end; ++i)
  {
    if constexpr (Springs)
    {
      springBlock<double>(topology, c, i, x, v, out);
    }
    else
    {
      volumeBlock<double>(topology, c, i, x, v, out);
    }
  }
}

template <bool Springs>
void elementRangeBaseline(const Topology& topology, const ElementConstants& c, std::size_t begin,
  std::size_t end, const double* x, const double* v, double* out)
{
  elementRange<double, Springs>(topology, c, begin, end, x, v, out);
}

#if SOFTBODY_HAVE_AVX2_PATH
template <bool Springs>
SOFTBODY_TARGET_AVX2 void elementRangeAvx2(const Topology& topology, const ElementConstants& c,
  std::size_t begin, std::size_t end, const double* x, const double* v, double* out)
{
  elementRange<simd::Lanes4, Springs>(topology, c, begin, end, x, v, out);
}
#endif

/// One element pass over all edges (Springs) or tets, in parallel chunks. Each element writes
/// only its own output, so any split gives the same result.
template <bool Springs>
void elementPass(const Topology& topology, const ElementConstants& c, const std::vector<Vec3>& positions,
  const std::vector<Vec3>& velocities, std::vector<Vec3>& out, SimdLevel level)
{
  const std::size_t count = Springs ? topology.edges.size() : topology.tets.size();
  const double* x = positions.data()->data();
  const double* v = velocities.data()->data();
  double* o = out.data()->data();
  const std::size_t chunks = (count + kElementChunk - 1) / kElementChunk;
  parallelFor(chunks, 1, [&](std::size_t k) {
    const std::size_t begin = k * kElementChunk;
    const std::size_t end = std::min(count, begin + kElementChunk);
#if SOFTBODY_HAVE_AVX2_PATH
    if (level == SimdLevel::Avx2)
    {
      elementRangeAvx2<Springs>(topology, c, begin, end, x, v, o);
      return;
    }
#endif
    elementRangeBaseline<Springs>(topology, c, begin, end, x, v, o);
  });
  (void)level;
}

} // namespace

void computeInternalForces(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, ForceScratch& scratch,
  std::vector<Vec3>& forces, SimdLevel level)
{
  scratch.springForce.resize(topology.edges.size());
  elementPass<true>(topology, constants, positions, velocities, scratch.springForce, level);
  if (constants.hasVolumeTerm)
  {
    scratch.tetCornerForce.resize(4 * topology.tets.size());
    elementPass<false>(topology, constants, positions, velocities, scratch.tetCornerForce, level);
  }

  // Pass 2: gather in CSR order (fixed), one writer per vertex: the spring ends, then (a second
  // loop that starts from the first one's sums, so the additions and their order are unchanged)
  // the tet corners. One loop over both would read two scattered streams at once (the spring
  // forces with the edges' ends, the corner forces) and run 0.6 ms slower per evaluation on one
  // thread on the 180k-tet TetGen ellipsoid (4.9 against 4.3 ms; the same at 2 threads).
  forces.resize(topology.vertexCount);
  parallelFor(topology.vertexCount, kVertexGrain, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    const Csr& edges = topology.vertexEdges;
    for (std::int32_t k = edges.offsets[i]; k < edges.offsets[i + 1]; ++k)
    {
      const std::int32_t e = edges.items[k];
      const Vec3& f = scratch.springForce[e];
      sum += (topology.edges[e].a == static_cast<std::int32_t>(i)) ? f : Vec3(-f);
    }
    forces[i] = sum;
  });
  if (constants.hasVolumeTerm)
  {
    parallelFor(topology.vertexCount, kVertexGrain, [&](std::size_t i) {
      Vec3 sum = forces[i];
      const Csr& corners = topology.vertexTetCorners;
      for (std::int32_t k = corners.offsets[i]; k < corners.offsets[i + 1]; ++k)
      {
        sum += scratch.tetCornerForce[static_cast<std::size_t>(corners.items[k])];
      }
      forces[i] = sum;
    });
  }
}

double elasticEnergy(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions)
{
  double energy = 0.0;
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
  {
    const Edge& edge = topology.edges[e];
    const double stretch = (positions[edge.a] - positions[edge.b]).norm() - constants.restLength[e];
    energy += 0.5 * constants.springStiffness[e] * stretch * stretch;
  }
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    const Tet& tet = topology.tets[t];
    const double dv = signedTetVolume(positions[tet[0]], positions[tet[1]], positions[tet[2]],
                        positions[tet[3]]) - constants.restVolume[t];
    energy += 0.5 * constants.volumeStiffness[t] * dv * dv;
  }
  return energy;
}

double maxStretchRatio(const Topology& topology, const ElementConstants& constants,
  const std::vector<Vec3>& positions)
{
  // max is order-independent, so the parallel reduction is deterministic. A NaN poisons the
  // result on purpose (std::max would silently drop it).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return parallelReduce(
    topology.edges.size(), kElementChunk, 0.0,
    [&](std::size_t e) {
      const Edge& edge = topology.edges[e];
      return (positions[edge.a] - positions[edge.b]).norm() / constants.restLength[e];
    },
    [nan](double l, double r) { return (std::isnan(l) || std::isnan(r)) ? nan : std::max(l, r); });
}

} // namespace softbody

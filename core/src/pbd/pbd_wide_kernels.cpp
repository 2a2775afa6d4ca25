#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic ignored "-Wpsabi" // 32-byte vectors passed between inlined helpers only
#endif

#include "softbody/pbd/pbd_wide_kernels.h"

namespace softbody
{
namespace
{
using simd::Lanes4;
using simd::lane;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are read as packed xyz triples");
static_assert(sizeof(ProjectionParameters) == 2 * sizeof(double), "scale, alphaTilde: a strided load");

/// Lanes [0, width) whose constraint is not broken, as bits.
template <class T>
SOFTBODY_SIMD_INLINE unsigned activeLanes(const unsigned char* broken)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return broken[0] == 0 ? 1u : 0u;
  }
  else
  {
    std::uint32_t bytes;
    __builtin_memcpy(&bytes, broken, sizeof(bytes));
    return (bytes & 0xffu ? 0u : 1u) | (bytes & 0xff00u ? 0u : 2u) | (bytes & 0xff0000u ? 0u : 4u) |
      (bytes & 0xff000000u ? 0u : 8u);
  }
}

/// Moves the corners of the active lanes to x + dx and adds dLambda to their multipliers. A
/// pinned corner (w = 0, dx = 0) is not written: pinned particles may be shared within a color
/// (the coloring only separates movable ones), and writing them would only be a redundant store.
template <class T, int N>
SOFTBODY_SIMD_INLINE void apply(const lanes::ProjectionLanes<T, N>& r, const simd::Vec3Lanes<T> (&x)[N],
  const T (&w)[N], const std::int32_t* corners, unsigned active, double* lambda, double* xyz)
{
  const T zero = simd::broadcast<T>(0.0);
  for (int k = 0; k < N; ++k)
  {
    simd::scatter3<T>(xyz, corners + k, N, x[k] + r.dx[k], active & simd::laneBits(w[k] > zero));
  }
  // Inactive lanes keep their multiplier's bits (adding 0 would turn -0 into +0).
  const T old = simd::load<T>(lambda);
  simd::store(lambda, simd::select(simd::laneMask<T>(active), old + r.dLambda, old));
}

template <class T>
SOFTBODY_SIMD_INLINE void projectBlock(DistanceBatch& batch, std::size_t c, double* xyz, const double* w)
{
  const unsigned active = activeLanes<T>(&batch.broken[c]);
  if (active == 0)
  {
    return;
  }
  const std::int32_t* ends = batch.ends[c].data();
  const double* params = &batch.params[c].scale;
  const simd::Vec3Lanes<T> x[2] = { simd::gather3<T>(xyz, ends, 2), simd::gather3<T>(xyz, ends + 1, 2) };
  const T wl[2] = { simd::gather<T>(w, ends, 2), simd::gather<T>(w, ends + 1, 2) };
  const auto r = lanes::distance<T>(x[0], x[1], wl[0], wl[1], simd::load<T>(&batch.rest[c]),
    batch.kind == DistanceKind::AtLeast, simd::load<T>(&batch.lambda[c]), simd::loadStrided<T>(params, 2),
    simd::loadStrided<T>(params + 1, 2));
  apply<T, 2>(r, x, wl, ends, active, &batch.lambda[c], xyz);
}

template <class T>
SOFTBODY_SIMD_INLINE void projectBlock(VolumeBatch& batch, std::size_t c, double* xyz, const double* w)
{
  const unsigned active = activeLanes<T>(&batch.broken[c]);
  if (active == 0)
  {
    return;
  }
  const std::int32_t* corners = batch.tets[c].data();
  const double* params = &batch.params[c].scale;
  const simd::Vec3Lanes<T> x[4] = { simd::gather3<T>(xyz, corners, 4), simd::gather3<T>(xyz, corners + 1, 4),
    simd::gather3<T>(xyz, corners + 2, 4), simd::gather3<T>(xyz, corners + 3, 4) };
  const T wl[4] = { simd::gather<T>(w, corners, 4), simd::gather<T>(w, corners + 1, 4),
    simd::gather<T>(w, corners + 2, 4), simd::gather<T>(w, corners + 3, 4) };
  const auto r = lanes::tetVolume<T>(x[0], x[1], x[2], x[3], wl, simd::load<T>(&batch.restVolume[c]),
    simd::load<T>(&batch.lambda[c]), simd::loadStrided<T>(params, 2), simd::loadStrided<T>(params + 1, 2));
  apply<T, 4>(r, x, wl, corners, active, &batch.lambda[c], xyz);
}

/// Blocks of `Lanes` (double: one constraint at a time), then the rest one at a time. Inlined
/// into one wrapper per SimdLevel, which compiles it for that level. The baseline level runs
/// one lane: the four-lane type lowered to SSE2 pairs runs at half the scalar speed (measured by
/// bench_wide_kernels), since the compiler moves such vectors through memory.
template <class Lanes, class Batch>
SOFTBODY_SIMD_INLINE void sweepRange(Batch& batch, std::size_t begin, std::size_t end, std::vector<Vec3>& x,
  const std::vector<double>& w)
{
  double* xyz = x.data()->data();
  std::size_t c = begin;
  if constexpr (!std::is_same_v<Lanes, double>)
  {
    for (; c + simd::kWidth <= end; c += simd::kWidth)
    {
      projectBlock<Lanes>(batch, c, xyz, w.data());
    }
  }
  for (; c < end; ++c)
  {
    projectBlock<double>(batch, c, xyz, w.data());
  }
}

/// The whole batch in order: independent blocks as one block of lanes, the others (and the
/// partial block at the end) one constraint at a time.
template <class Lanes, class Batch>
SOFTBODY_SIMD_INLINE void sequentialSweep(
  Batch& batch, const std::vector<char>& independent, std::vector<Vec3>& x, const std::vector<double>& w)
{
  double* xyz = x.data()->data();
  std::size_t c = 0;
  if constexpr (!std::is_same_v<Lanes, double>)
  {
    for (std::size_t b = 0; b < independent.size(); ++b, c += simd::kWidth)
    {
      if (independent[b] != 0)
      {
        projectBlock<Lanes>(batch, c, xyz, w.data());
      }
      else
      {
        for (std::size_t k = 0; k < static_cast<std::size_t>(simd::kWidth); ++k)
        {
          projectBlock<double>(batch, c + k, xyz, w.data());
        }
      }
    }
  }
  for (; c < batch.size(); ++c)
  {
    projectBlock<double>(batch, c, xyz, w.data());
  }
}

void linksBaseline(DistanceBatch& b, std::size_t begin, std::size_t end, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sweepRange<double>(b, begin, end, x, w);
}
void volumesBaseline(VolumeBatch& b, std::size_t begin, std::size_t end, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sweepRange<double>(b, begin, end, x, w);
}
void sequentialLinksBaseline(
  DistanceBatch& b, const std::vector<char>& independent, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sequentialSweep<double>(b, independent, x, w);
}
void sequentialVolumesBaseline(
  VolumeBatch& b, const std::vector<char>& independent, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sequentialSweep<double>(b, independent, x, w);
}
#if SOFTBODY_HAVE_AVX2_PATH
SOFTBODY_TARGET_AVX2 void sequentialLinksAvx2(
  DistanceBatch& b, const std::vector<char>& independent, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sequentialSweep<Lanes4>(b, independent, x, w);
}
SOFTBODY_TARGET_AVX2 void sequentialVolumesAvx2(
  VolumeBatch& b, const std::vector<char>& independent, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sequentialSweep<Lanes4>(b, independent, x, w);
}
#endif
#if SOFTBODY_HAVE_AVX2_PATH
SOFTBODY_TARGET_AVX2 void linksAvx2(
  DistanceBatch& b, std::size_t begin, std::size_t end, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sweepRange<Lanes4>(b, begin, end, x, w);
}
SOFTBODY_TARGET_AVX2 void volumesAvx2(
  VolumeBatch& b, std::size_t begin, std::size_t end, std::vector<Vec3>& x, const std::vector<double>& w)
{
  sweepRange<Lanes4>(b, begin, end, x, w);
}
#endif
} // namespace

void projectLinksWide(DistanceBatch& batch, std::size_t begin, std::size_t end, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level)
{
#if SOFTBODY_HAVE_AVX2_PATH
  if (level == SimdLevel::Avx2)
  {
    linksAvx2(batch, begin, end, x, w);
    return;
  }
#endif
  (void)level;
  linksBaseline(batch, begin, end, x, w);
}

void projectVolumesWide(VolumeBatch& batch, std::size_t begin, std::size_t end, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level)
{
#if SOFTBODY_HAVE_AVX2_PATH
  if (level == SimdLevel::Avx2)
  {
    volumesAvx2(batch, begin, end, x, w);
    return;
  }
#endif
  (void)level;
  volumesBaseline(batch, begin, end, x, w);
}

void gaussSeidelLinksWide(DistanceBatch& batch, const std::vector<char>& independent, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level)
{
#if SOFTBODY_HAVE_AVX2_PATH
  if (level == SimdLevel::Avx2)
  {
    sequentialLinksAvx2(batch, independent, x, w);
    return;
  }
#endif
  (void)level;
  sequentialLinksBaseline(batch, independent, x, w);
}

void gaussSeidelVolumesWide(VolumeBatch& batch, const std::vector<char>& independent, std::vector<Vec3>& x,
  const std::vector<double>& w, SimdLevel level)
{
#if SOFTBODY_HAVE_AVX2_PATH
  if (level == SimdLevel::Avx2)
  {
    sequentialVolumesAvx2(batch, independent, x, w);
    return;
  }
#endif
  (void)level;
  sequentialVolumesBaseline(batch, independent, x, w);
}

} // namespace softbody

// Four doubles at a time, for the element and constraint kernels.
//
// The lane type is a GCC/Clang vector extension, so the kernels are plain arithmetic written
// once as templates over the lane type (`double` for one element, `Lanes4` for four), with no
// intrinsics. The same source is compiled twice where it is called:
//   - a baseline copy (x86-64's SSE2: the compiler splits each 4-lane operation in two), which
//     runs on any x86-64;
//   - an AVX2 copy, through `SOFTBODY_TARGET_AVX2` on the calling function (GCC/Clang `target`
//     attribute), chosen at run time by `bestSimdLevel()` (cpuid).
// The build itself stays portable (no -march): only those functions use AVX instructions.
// The helpers here are always inlined, so they are compiled with their caller's target; an
// out-of-line copy would be compiled for the baseline, never the other way round.
//
// Results are the same bit for bit in every copy and equal to the one-lane instantiation:
// each lane does the same IEEE operations in the same order (+ - * / sqrt are correctly
// rounded; no FMA is enabled, so nothing is contracted). Rejected: `-march=native` (a binary
// that dies on an older CPU) and FMA (faster, but results would differ between machines).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>


#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic push
// Passing 32-byte vectors by value without AVX "changes the ABI": irrelevant here, every
// function taking them is inlined.
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#define SOFTBODY_SIMD_INLINE inline __attribute__((always_inline))
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SOFTBODY_HAVE_AVX2_PATH 1
#define SOFTBODY_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define SOFTBODY_HAVE_AVX2_PATH 0
#define SOFTBODY_TARGET_AVX2
#endif

namespace softbody
{

/// Which compiled copy of a wide kernel runs.
enum class SimdLevel
{
  Baseline, ///< any x86-64 (SSE2), or plain code elsewhere
  Avx2      ///< 256-bit lanes; only where the CPU has AVX2
};

/// The widest level this CPU runs (AVX2 where cpuid says so), decided once.
inline SimdLevel bestSimdLevel()
{
#if SOFTBODY_HAVE_AVX2_PATH
  static const SimdLevel level = __builtin_cpu_supports("avx2") ? SimdLevel::Avx2 : SimdLevel::Baseline;
  return level;
#else
  return SimdLevel::Baseline;
#endif
}

inline const char* simdLevelName(SimdLevel level)
{
  return level == SimdLevel::Avx2 ? "AVX2" : "baseline";
}

namespace simd
{

/// Four double lanes, and a lane mask (all bits set where true) as comparisons return it.
using Lanes4 = double __attribute__((vector_size(32)));
using Mask4 = std::int64_t __attribute__((vector_size(32)));
using Pair = double __attribute__((vector_size(16))); ///< a point's x and y
constexpr int kWidth = 4;

/// Every lane set to v (one lane: v itself).
template <class T>
SOFTBODY_SIMD_INLINE T broadcast(double v)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return v;
  }
  else
  {
    return T{ v, v, v, v };
  }
}

/// a where the mask is set, else b.
SOFTBODY_SIMD_INLINE double select(bool mask, double a, double b)
{
  return mask ? a : b;
}
SOFTBODY_SIMD_INLINE Lanes4 select(Mask4 mask, Lanes4 a, Lanes4 b)
{
  return mask ? a : b;
}

/// Lane masks combined (one lane: bools).
SOFTBODY_SIMD_INLINE bool both(bool a, bool b)
{
  return a && b;
}
SOFTBODY_SIMD_INLINE Mask4 both(Mask4 a, Mask4 b)
{
  return a & b;
}
SOFTBODY_SIMD_INLINE bool negate(bool a)
{
  return !a;
}
SOFTBODY_SIMD_INLINE Mask4 negate(Mask4 a)
{
  return ~a;
}

/// Whether any lane of a mask is set (one lane: the bool).
SOFTBODY_SIMD_INLINE bool any(bool mask)
{
  return mask;
}
SOFTBODY_SIMD_INLINE bool any(Mask4 mask)
{
  return (mask[0] | mask[1] | mask[2] | mask[3]) != 0;
}

/// Lane-wise sqrt. Four scalar square roots (correctly rounded, so equal to one vsqrtpd); the
/// vector extension has no sqrt and an intrinsic would tie the header to one target. Core is
/// compiled with -fno-math-errno (core/CMakeLists.txt), without which GCC keeps four scalar
/// sqrtsd, each followed by a branch to libm for errno; with it the AVX2 copies get one vsqrtpd.
SOFTBODY_SIMD_INLINE double sqrt(double v)
{
  return __builtin_sqrt(v);
}
SOFTBODY_SIMD_INLINE Lanes4 sqrt(Lanes4 v)
{
  return Lanes4{ __builtin_sqrt(v[0]), __builtin_sqrt(v[1]), __builtin_sqrt(v[2]), __builtin_sqrt(v[3]) };
}

/// Lane l of a value (one lane: the value).
SOFTBODY_SIMD_INLINE double lane(double v, int)
{
  return v;
}
SOFTBODY_SIMD_INLINE double lane(Lanes4 v, int l)
{
  return v[l];
}
SOFTBODY_SIMD_INLINE bool lane(bool m, int)
{
  return m;
}
SOFTBODY_SIMD_INLINE bool lane(Mask4 m, int l)
{
  return m[l] != 0;
}

/// A 3-vector of lanes: component arrays, so every operation works on four elements at once.
template <class T>
struct Vec3Lanes
{
  T x, y, z;
};

template <class T>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> operator-(const Vec3Lanes<T>& a, const Vec3Lanes<T>& b)
{
  return { a.x - b.x, a.y - b.y, a.z - b.z };
}
template <class T>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> operator+(const Vec3Lanes<T>& a, const Vec3Lanes<T>& b)
{
  return { a.x + b.x, a.y + b.y, a.z + b.z };
}
template <class T>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> operator-(const Vec3Lanes<T>& a)
{
  return { -a.x, -a.y, -a.z };
}
template <class T>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> operator*(T s, const Vec3Lanes<T>& a)
{
  return { s * a.x, s * a.y, s * a.z };
}
template <class T>
SOFTBODY_SIMD_INLINE T dot(const Vec3Lanes<T>& a, const Vec3Lanes<T>& b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> cross(const Vec3Lanes<T>& a, const Vec3Lanes<T>& b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}

/// Loads point idx[l * stride] of an array of xyz triples into lane l (`stride` steps over the
/// other indices of an index record, e.g. 2 for an edge's ends). Four points are transposed:
/// each point's x and y move as one 16-byte pair, z alone (never reading past a point's 24
/// bytes). Against lane-by-lane inserts this takes a third of the shuffles, and the shuffle
/// port is what limits the kernels with such inserts.
template <class T, class Index>
SOFTBODY_SIMD_INLINE Vec3Lanes<T> gather3(const double* xyz, const Index* idx, std::size_t stride)
{
  if constexpr (std::is_same_v<T, double>)
  {
    const double* p = xyz + 3 * static_cast<std::size_t>(idx[0]);
    return { p[0], p[1], p[2] };
  }
  else
  {
    const double* p0 = xyz + 3 * static_cast<std::size_t>(idx[0]);
    const double* p1 = xyz + 3 * static_cast<std::size_t>(idx[stride]);
    const double* p2 = xyz + 3 * static_cast<std::size_t>(idx[2 * stride]);
    const double* p3 = xyz + 3 * static_cast<std::size_t>(idx[3 * stride]);
    Pair xy0, xy1, xy2, xy3;
    __builtin_memcpy(&xy0, p0, sizeof(Pair));
    __builtin_memcpy(&xy1, p1, sizeof(Pair));
    __builtin_memcpy(&xy2, p2, sizeof(Pair));
    __builtin_memcpy(&xy3, p3, sizeof(Pair));
    const Lanes4 xy02 = __builtin_shufflevector(xy0, xy2, 0, 1, 2, 3); // x0 y0 x2 y2
    const Lanes4 xy13 = __builtin_shufflevector(xy1, xy3, 0, 1, 2, 3); // x1 y1 x3 y3
    const Pair z01 = { p0[2], p1[2] };
    const Pair z23 = { p2[2], p3[2] };
    return { __builtin_shufflevector(xy02, xy13, 0, 4, 2, 6), __builtin_shufflevector(xy02, xy13, 1, 5, 3, 7),
      __builtin_shufflevector(z01, z23, 0, 1, 2, 3) };
  }
}

/// Writes lane l of v as point idx[l * stride] of an xyz array, for the lanes whose bit is set
/// in `lanesToWrite`, in lane order (the transpose of gather3).
template <class T, class Index>
SOFTBODY_SIMD_INLINE void scatter3(double* xyz, const Index* idx, std::size_t stride, const Vec3Lanes<T>& v,
  unsigned lanesToWrite)
{
  if constexpr (std::is_same_v<T, double>)
  {
    if (lanesToWrite & 1u)
    {
      double* p = xyz + 3 * static_cast<std::size_t>(idx[0]);
      p[0] = v.x;
      p[1] = v.y;
      p[2] = v.z;
    }
  }
  else
  {
    const Lanes4 xy02 = __builtin_shufflevector(v.x, v.y, 0, 4, 2, 6); // x0 y0 x2 y2
    const Lanes4 xy13 = __builtin_shufflevector(v.x, v.y, 1, 5, 3, 7); // x1 y1 x3 y3
    const Pair pairs[4] = { __builtin_shufflevector(xy02, xy02, 0, 1), __builtin_shufflevector(xy13, xy13, 0, 1),
      __builtin_shufflevector(xy02, xy02, 2, 3), __builtin_shufflevector(xy13, xy13, 2, 3) };
    for (int l = 0; l < kWidth; ++l)
    {
      if ((lanesToWrite >> l) & 1u)
      {
        double* p = xyz + 3 * static_cast<std::size_t>(idx[static_cast<std::size_t>(l) * stride]);
        __builtin_memcpy(p, &pairs[l], sizeof(Pair));
        p[2] = v.z[l];
      }
    }
  }
}

/// Loads value idx[l * stride] into lane l.
template <class T, class Index>
SOFTBODY_SIMD_INLINE T gather(const double* values, const Index* idx, std::size_t stride)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return values[idx[0]];
  }
  else
  {
    return T{ values[idx[0]], values[idx[stride]], values[idx[2 * stride]], values[idx[3 * stride]] };
  }
}

/// Loads values[0..width) into the lanes (a contiguous load).
template <class T>
SOFTBODY_SIMD_INLINE T load(const double* values)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return values[0];
  }
  else
  {
    T v;
    __builtin_memcpy(&v, values, sizeof(T));
    return v;
  }
}

/// Stores the lanes to values[0..width).
SOFTBODY_SIMD_INLINE void store(double* values, double v)
{
  values[0] = v;
}
SOFTBODY_SIMD_INLINE void store(double* values, Lanes4 v)
{
  __builtin_memcpy(values, &v, sizeof(v));
}

/// The lane mask of the bits set in `bits` (the inverse of laneBits).
template <class T>
SOFTBODY_SIMD_INLINE auto laneMask(unsigned bits)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return (bits & 1u) != 0;
  }
  else
  {
    return Mask4{ -static_cast<std::int64_t>(bits & 1u), -static_cast<std::int64_t>((bits >> 1) & 1u),
      -static_cast<std::int64_t>((bits >> 2) & 1u), -static_cast<std::int64_t>((bits >> 3) & 1u) };
  }
}

/// Loads the first field of consecutive records of `stride` doubles (records[l * stride]).
template <class T>
SOFTBODY_SIMD_INLINE T loadStrided(const double* records, std::size_t stride)
{
  if constexpr (std::is_same_v<T, double>)
  {
    return records[0];
  }
  else
  {
    return T{ records[0], records[stride], records[2 * stride], records[3 * stride] };
  }
}

/// Bit l set where lane l of the mask is set.
SOFTBODY_SIMD_INLINE unsigned laneBits(bool m)
{
  return m ? 1u : 0u;
}
SOFTBODY_SIMD_INLINE unsigned laneBits(Mask4 m)
{
  return (m[0] != 0 ? 1u : 0u) | (m[1] != 0 ? 2u : 0u) | (m[2] != 0 ? 4u : 0u) | (m[3] != 0 ? 8u : 0u);
}

} // namespace simd
} // namespace softbody

#if defined(__GNUC__) // GCC and Clang
#pragma GCC diagnostic pop
#endif

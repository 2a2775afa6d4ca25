// The PBD/XPBD solvers, written once against the batch interface of pbd_constraints.h:
//   Gauss-Seidel (and SOR: the batch's params carry the relaxation factor), each projection
//     applied at once, in constraint order;
//   parallel Gauss-Seidel: the same projections color by color (graph_coloring.h), each color's
//     constraints in parallel; no two of them share a particle, so nothing races and the result
//     is the same at any thread count (it differs from sequential Gauss-Seidel only in order);
//   averaged Jacobi: every projection computed from the same positions, then each particle moves
//     by the relaxed mean of the corrections asked of it (Macklin et al. 2014), gathered per
//     particle so no two threads write one particle.
#pragma once

#include "softbody/mesh/graph_coloring.h"
#include "softbody/common/parallel.h"
#include "softbody/pbd/pbd_wide_kernels.h"

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace softbody
{

/// Everything a solver needs about a batch besides the batch: which constraint slots touch each
/// particle (Jacobi's gather) and the coloring (parallel Gauss-Seidel). Built once per body.
struct BatchSchedule
{
  Csr particleSlots; ///< particle -> c * Arity + k
  Coloring coloring;
  /// The batch is stored color by color (coloring.order is the identity): the colored solver
  /// then runs the wide kernels over each color's contiguous range.
  bool storedByColor = false;
  /// Sequential Gauss-Seidel: per block of four consecutive constraints, whether they share no
  /// particle (pbd_wide_kernels.h, independentBlocks); empty: one constraint at a time.
  std::vector<char> independentBlocks;
};

template <class Batch>
std::vector<std::int32_t> flattenParticles(const Batch& batch)
{
  std::vector<std::int32_t> flat(batch.size() * Batch::Arity);
  for (std::size_t c = 0; c < batch.size(); ++c)
  {
    for (int k = 0; k < Batch::Arity; ++k)
    {
      flat[c * Batch::Arity + static_cast<std::size_t>(k)] = batch.particles(c)[k];
    }
  }
  return flat;
}

template <class Batch>
BatchSchedule makeSchedule(const Batch& batch, std::size_t particleCount, const std::vector<char>& movable)
{
  const std::vector<std::int32_t> flat = flattenParticles(batch);
  BatchSchedule schedule;
  schedule.particleSlots = particleSlots(particleCount, flat);
  schedule.coloring = colorConstraints(particleCount, flat, Batch::Arity, movable);
  return schedule;
}

namespace detail
{
template <class Batch>
inline void projectAndApply(Batch& batch, std::size_t c, std::vector<Vec3>& x, const std::vector<double>& w)
{
  if (!batch.active(c))
  {
    return;
  }
  const auto projection = batch.project(c, x, w);
  const std::int32_t* p = batch.particles(c);
  for (int k = 0; k < Batch::Arity; ++k)
  {
    x[static_cast<std::size_t>(p[k])] += projection.dx[static_cast<std::size_t>(k)];
  }
  batch.lambda[c] += projection.dLambda;
}
} // namespace detail

/// The storage order of sequential Gauss-Seidel's batches (PbdSimulation): [0, count) cut into
/// `streams` contiguous parts, taking one index of each part in turn (0, p, 2p, 3p, 1, p + 1,
/// ...; p = ceil(count / streams)). Consecutive projections then rarely share a particle and the
/// core overlaps them; each part keeps the order it had (by vertex: cache).
inline std::vector<std::int32_t> interleavedStreams(std::size_t count, std::size_t streams = 4)
{
  std::vector<std::int32_t> order;
  order.reserve(count);
  const std::size_t part = (count + streams - 1) / streams;
  for (std::size_t i = 0; i < part; ++i)
  {
    for (std::size_t s = 0; s < streams; ++s)
    {
      if (s * part + i < count)
      {
        order.push_back(static_cast<std::int32_t>(s * part + i));
      }
    }
  }
  return order;
}

template <class Batch>
void gaussSeidelSweep(Batch& batch, std::vector<Vec3>& x, const std::vector<double>& w)
{
  for (std::size_t c = 0; c < batch.size(); ++c)
  {
    detail::projectAndApply(batch, c, x, w);
  }
}

/// Sequential Gauss-Seidel with the wide kernels on the blocks the schedule marks independent:
/// the same result bit for bit as gaussSeidelSweep.
template <class Batch>
void gaussSeidelSweep(Batch& batch, const BatchSchedule& schedule, std::vector<Vec3>& x, const std::vector<double>& w)
{
  if constexpr (std::is_same_v<Batch, DistanceBatch>)
  {
    if (!schedule.independentBlocks.empty())
    {
      gaussSeidelLinksWide(batch, schedule.independentBlocks, x, w);
      return;
    }
  }
  else if constexpr (std::is_same_v<Batch, VolumeBatch>)
  {
    if (!schedule.independentBlocks.empty())
    {
      gaussSeidelVolumesWide(batch, schedule.independentBlocks, x, w);
      return;
    }
  }
  gaussSeidelSweep(batch, x, w);
}

template <class Batch>
void coloredGaussSeidelSweep(
  Batch& batch, const BatchSchedule& schedule, std::vector<Vec3>& x, const std::vector<double>& w)
{
  constexpr bool hasWideKernel = std::is_same_v<Batch, DistanceBatch> || std::is_same_v<Batch, VolumeBatch>;
  const Coloring& coloring = schedule.coloring;
  for (std::size_t color = 0; color < coloring.colorCount(); ++color)
  {
    const std::size_t begin = static_cast<std::size_t>(coloring.colorOffsets[color]);
    const std::size_t end = static_cast<std::size_t>(coloring.colorOffsets[color + 1]);
    // One contiguous part of the color per thread, the same part every color: the constraints
    // are stored sorted by their vertices within each color (pbd_setup.cpp, mesh/reorder.h), so
    // each core works on the same region of the body color after color. With TBB's dynamic
    // split the parts would move between the cores every color, pulling the vertices' cache
    // lines across with them: 2 threads would run slower than 1.
    if constexpr (hasWideKernel)
    {
      if (schedule.storedByColor)
      {
        // Chunks of whole lane blocks; any split gives the same result (pbd_wide_kernels.h).
        constexpr std::size_t kChunk = 256;
        static_assert(kChunk % simd::kWidth == 0);
        const std::size_t chunks = (end - begin + kChunk - 1) / kChunk;
        parallelForContiguous(chunks, 1, [&](std::size_t k) {
          const std::size_t first = begin + k * kChunk;
          const std::size_t last = std::min(end, first + kChunk);
          if constexpr (std::is_same_v<Batch, DistanceBatch>)
          {
            projectLinksWide(batch, first, last, x, w);
          }
          else
          {
            projectVolumesWide(batch, first, last, x, w);
          }
        });
        continue;
      }
    }
    parallelForContiguous(end - begin, 256, [&](std::size_t i) {
      detail::projectAndApply(batch, static_cast<std::size_t>(coloring.order[begin + i]), x, w);
    });
  }
}

/// `slotCorrection` is scratch (resized here). Only corrections that are nonzero count toward a
/// particle's average, so a satisfied inequality does not dilute the others.
template <class Batch>
void jacobiSweep(Batch& batch, const BatchSchedule& schedule, double relaxation,
  std::vector<Vec3>& x, const std::vector<double>& w, std::vector<Vec3>& slotCorrection)
{
  slotCorrection.resize(batch.size() * Batch::Arity);
  parallelFor(batch.size(), 256, [&](std::size_t c) {
    Vec3* out = &slotCorrection[c * Batch::Arity];
    if (!batch.active(c))
    {
      for (int k = 0; k < Batch::Arity; ++k)
      {
        out[k].setZero();
      }
      return;
    }
    const auto projection = batch.project(c, x, w);
    for (int k = 0; k < Batch::Arity; ++k)
    {
      out[k] = projection.dx[static_cast<std::size_t>(k)];
    }
    batch.lambda[c] += projection.dLambda;
  });
  const Csr& slots = schedule.particleSlots;
  parallelFor(x.size(), 512, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    int contributing = 0;
    for (std::int32_t s = slots.offsets[i]; s < slots.offsets[i + 1]; ++s)
    {
      const Vec3& dx = slotCorrection[static_cast<std::size_t>(slots.items[static_cast<std::size_t>(s)])];
      if (dx.squaredNorm() > 0.0)
      {
        sum += dx;
        ++contributing;
      }
    }
    if (contributing > 0)
    {
      x[i] += (relaxation / contributing) * sum;
    }
  });
}

/// Sum over the batch's active constraints of (C + alphaTilde lambda)^2 at positions x, summed in
/// fixed blocks so the value does not depend on the thread count.
template <class Batch>
double squaredResidual(const Batch& batch, const std::vector<Vec3>& x, const std::vector<double>& w)
{
  constexpr std::size_t kBlock = 2048;
  const std::size_t blocks = (batch.size() + kBlock - 1) / kBlock;
  std::vector<double> partial(blocks, 0.0);
  parallelFor(blocks, 1, [&](std::size_t b) {
    double sum = 0.0;
    const std::size_t end = std::min(batch.size(), (b + 1) * kBlock);
    for (std::size_t c = b * kBlock; c < end; ++c)
    {
      if (batch.active(c))
      {
        const double r = batch.project(c, x, w).residual;
        sum += r * r;
      }
    }
    partial[b] = sum;
  });
  double total = 0.0;
  for (double value : partial)
  {
    total += value;
  }
  return total;
}

} // namespace softbody

// A STREAM-style triad probe: the memory bandwidth this machine sustains, measured in the same
// process as the benchmark so their ratio is meaningful.
#pragma once

#include <cstddef>

namespace softbody::bench
{

/// Sustained bandwidth [bytes/s] of a[i] = b[i] + s c[i] over arrays far larger than the
/// caches, run with the current TBB parallelism. Counts 3 streams of 8-byte doubles (no
/// write-allocate), as STREAM does.
double measureTriadBandwidth(std::size_t elements, int repetitions);

/// How many cores this process actually gets at the current TBB parallelism: the work rate of a
/// compute-bound loop (no memory traffic) over the rate of the same loop on the calling thread
/// alone. 2.0 on an idle 2-core machine; near 1 when other processes hold the second core, and
/// then no parallel speed-up above it can be measured.
double measureComputeParallelism(int repetitions);

} // namespace softbody::bench

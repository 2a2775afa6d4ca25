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

} // namespace softbody::bench

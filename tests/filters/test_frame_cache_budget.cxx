// filter.frame_cache_budget: the frame cache under a partial memory budget (room for three
// frames): least-recently-used eviction, a lookup counting as a use, frame 0 never evicted,
// replacing a frame not counted twice, the latest frame at or before a time found, and a
// shrinking budget evicting at once. (filter.frame_cache covers a zero budget through the
// filter; CacheMemoryLimit is in MiB, too coarse to leave room for a few frames of a small body.)
#include "vtkSoftBodyFrameCache.h"

#include <cstdio>
#include <set>

namespace
{
int failures = 0;
void Check(bool ok, const char* what)
{
  if (!ok)
  {
    std::printf("FAILED: %s\n", what);
    ++failures;
  }
}

softbody::DynamicState Frame(int k)
{
  softbody::DynamicState state;
  state.positions.assign(1000, softbody::Vec3(k, 0, 0));
  state.velocities.assign(1000, softbody::Vec3::Zero());
  state.time = 0.1 * k;
  return state;
}

std::set<int> Cached(const vtkSoftBodyFrameCache& cache, int upTo)
{
  std::set<int> frames;
  for (int k = 0; k <= upTo; ++k)
  {
    if (cache.Contains(k))
    {
      frames.insert(k);
    }
  }
  return frames;
}
} // namespace

int main()
{
  const std::size_t frameBytes = vtkSoftBodyFrameCache::SizeOf(Frame(0));
  vtkSoftBodyFrameCache cache;
  cache.SetMemoryLimit(frameBytes * 7 / 2); // three frames fit, four do not
  for (int k = 0; k <= 2; ++k)
  {
    cache.Insert(k, Frame(k));
  }
  Check(Cached(cache, 9) == std::set<int>{ 0, 1, 2 }, "three frames fit");
  Check(cache.GetMemoryUsed() == 3 * frameBytes, "memory counts three frames");

  cache.Insert(3, Frame(3)); // evicts frame 1, the least recently used after frame 0
  Check(Cached(cache, 9) == std::set<int>{ 0, 2, 3 }, "frame 1 evicted (least recently used)");

  int found = -1;
  const softbody::DynamicState* state = cache.FindLatestAtOrBefore(2, found);
  Check(found == 2 && state && state->positions[0].x() == 2.0, "frame 2 found for index 2");
  cache.Insert(4, Frame(4)); // frame 2 was just used: frame 3 goes
  Check(Cached(cache, 9) == std::set<int>{ 0, 2, 4 }, "a lookup counts as a use: frame 3 evicted");
  Check(cache.GetMemoryUsed() <= cache.GetMemoryLimit(), "within the budget");

  state = cache.FindLatestAtOrBefore(3, found);
  Check(found == 2 && state && state->time == 0.2, "index 3 resumes from frame 2");
  state = cache.FindLatestAtOrBefore(1, found);
  Check(found == 0 && state && state->time == 0.0, "index 1 resumes from frame 0");

  cache.Insert(4, Frame(4)); // replacing a frame costs nothing more
  Check(Cached(cache, 9) == std::set<int>{ 0, 2, 4 } && cache.GetMemoryUsed() == 3 * frameBytes,
    "replacing frame 4 evicts nothing");

  for (int k = 5; k <= 9; ++k)
  {
    cache.Insert(k, Frame(k));
    Check(cache.Contains(0) && cache.Contains(k) && cache.GetNumberOfFrames() == 3, "frame 0 and the newest stay");
  }
  cache.SetMemoryLimit(frameBytes / 2); // not even frame 0 fits: it stays anyway, alone
  Check(Cached(cache, 9) == std::set<int>{ 0 }, "shrinking the budget evicts at once, frame 0 stays");
  if (failures == 0)
  {
    std::printf("filter.frame_cache_budget: all checks passed\n");
  }
  return failures == 0 ? 0 : 1;
}

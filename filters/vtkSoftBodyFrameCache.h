/**
 * @class   vtkSoftBodyFrameCache
 * @brief   Snapshots of a soft-body simulation at frame times, within a memory budget.
 *
 * Also defines vtkSoftBodyFrameGrid, the frame times whose indices key the cache.
 *
 * The filter's time grid is t_k = k * FrameInterval. Each cached frame k holds the complete
 * softbody::DynamicState at t_k, so a request for time t resumes from the latest cached frame at
 * or before t instead of from t = 0, and a request for a cached frame costs no simulation at all.
 *
 * Eviction is least-recently-used, except frame 0 (the initial state): it is the one snapshot
 * every request can always fall back to, so it is never evicted whatever the budget.
 *
 * Plain C++ (not a vtkObject): it is private to the filter and never crosses the wrapping.
 */
#ifndef vtkSoftBodyFrameCache_h
#define vtkSoftBodyFrameCache_h

#include "softbody/integrators/explicit_integrators.h" // softbody::DynamicState

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

/**
 * The frame grid t_k = k * FrameInterval, k = 0..LastFrame(), closed by EndTime: the times the
 * filter advertises and the frame indices the cache is keyed by.
 */
struct vtkSoftBodyFrameGrid
{
  /// Relative tolerance under which a time counts as lying on the grid: absorbs the rounding of
  /// k * FrameInterval and of times typed or computed by the user.
  static constexpr double Tolerance = 1e-9;
  double FrameInterval; ///< [s], > 0
  double EndTime;       ///< [s], > 0

  /// Index of the last grid frame at or before EndTime (EndTime itself when it is on the grid).
  int LastFrame() const
  {
    const double n = this->EndTime / this->FrameInterval;
    const double nearest = std::round(n);
    if (std::abs(nearest - n) <= Tolerance * std::max(n, 1.0))
    {
      return static_cast<int>(nearest);
    }
    return static_cast<int>(std::floor(n));
  }

  /// The times to advertise: the grid frames, then EndTime when it is off the grid. A grid
  /// frame that only differs from EndTime by rounding is advertised as EndTime itself, so that
  /// TIME_STEPS and TIME_RANGE agree to the last bit.
  std::vector<double> Times() const
  {
    const int last = this->LastFrame();
    std::vector<double> times(static_cast<std::size_t>(last) + 1);
    for (int k = 0; k <= last; ++k)
    {
      times[static_cast<std::size_t>(k)] = k * this->FrameInterval;
    }
    if (this->IsOnGrid(this->EndTime, last))
    {
      times.back() = this->EndTime;
    }
    else
    {
      times.push_back(this->EndTime);
    }
    return times;
  }

  bool IsOnGrid(double t, int k) const
  {
    return std::abs(k * this->FrameInterval - t) <=
      Tolerance * std::max(std::abs(t), this->FrameInterval);
  }

  /// The grid frame a time t in [0, EndTime] falls on (onGrid) or follows (!onGrid).
  int FrameOf(double t, bool& onGrid) const
  {
    const int last = this->LastFrame();
    const int nearest = std::min(static_cast<int>(std::round(t / this->FrameInterval)), last);
    onGrid = this->IsOnGrid(t, nearest);
    if (onGrid)
    {
      return nearest;
    }
    return std::min(static_cast<int>(std::floor(t / this->FrameInterval)), last);
  }
};

class vtkSoftBodyFrameCache
{
public:
  /// Memory budget in bytes; shrinking it evicts at once.
  void SetMemoryLimit(std::size_t bytes);
  std::size_t GetMemoryLimit() const { return this->MemoryLimit; }

  /// Stores (or replaces) the snapshot of frame `index`, then evicts down to the budget.
  void Insert(int index, const softbody::DynamicState& state);

  /// The latest cached frame with index <= `index`, or nullptr when there is none. Marks it as
  /// recently used. `foundIndex` receives its index.
  const softbody::DynamicState* FindLatestAtOrBefore(int index, int& foundIndex);

  bool Contains(int index) const { return this->Frames.count(index) != 0; }
  /// Forgets the frames after `index` (they are simulated anew).
  void DropAfter(int index);
  std::size_t GetNumberOfFrames() const { return this->Frames.size(); }
  std::size_t GetMemoryUsed() const { return this->MemoryUsed; }
  void Clear();

  /// Bytes a snapshot occupies (the two per-point vector arrays dominate).
  static std::size_t SizeOf(const softbody::DynamicState& state);

private:
  struct Entry
  {
    softbody::DynamicState State;
    std::size_t Bytes = 0;
    unsigned long long LastUse = 0; ///< value of UseClock at the last insert or lookup
  };

  void EvictToLimit();

  std::map<int, Entry> Frames;
  std::size_t MemoryLimit = std::size_t(512) << 20;
  std::size_t MemoryUsed = 0;
  unsigned long long UseClock = 0;
};

#endif

// GPU-side time per stage, from GL_TIME_ELAPSED queries: host wall time would only measure how
// fast commands are queued. Queries are read when the host synchronizes anyway (collect()),
// so timing adds no stalls. Use on the GL thread.
#pragma once

#include <GL/glcorearb.h>

#include <cstddef>
#include <vector>

namespace softbody::gpu
{

class StageClock
{
public:
  explicit StageClock(std::size_t stageCount);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  /// Times the GL commands issued until end() and adds them to `stage` at the next collect().
  /// One interval at a time (GL allows no nested elapsed-time queries).
  void begin(std::size_t stage);
  void end();
  /// Adds the finished intervals to seconds(); waits for the GPU where they are not done.
  void collect();
  const std::vector<double>& seconds() const { return Seconds; }

private:
  struct Pending
  {
    GLuint query;
    std::size_t stage;
  };
  std::vector<double> Seconds;
  std::vector<GLuint> FreeQueries;
  std::vector<Pending> InFlight;
};

} // namespace softbody::gpu

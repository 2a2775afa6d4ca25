#include "stage_clock.h"

namespace softbody::gpu
{

StageClock::StageClock(std::size_t stageCount)
  : Seconds(stageCount, 0.0)
{
}

StageClock::~StageClock()
{
  for (const Pending& pending : InFlight)
  {
    FreeQueries.push_back(pending.query);
  }
  if (!FreeQueries.empty())
  {
    glDeleteQueries(static_cast<GLsizei>(FreeQueries.size()), FreeQueries.data());
  }
}

void StageClock::begin(std::size_t stage)
{
  GLuint query = 0;
  if (FreeQueries.empty())
  {
    glGenQueries(1, &query);
  }
  else
  {
    query = FreeQueries.back();
    FreeQueries.pop_back();
  }
  glBeginQuery(GL_TIME_ELAPSED, query);
  InFlight.push_back({ query, stage });
}

void StageClock::end()
{
  glEndQuery(GL_TIME_ELAPSED);
}

void StageClock::collect()
{
  for (const Pending& pending : InFlight)
  {
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(pending.query, GL_QUERY_RESULT, &nanoseconds);
    Seconds[pending.stage] += 1e-9 * static_cast<double>(nanoseconds);
    FreeQueries.push_back(pending.query);
  }
  InFlight.clear();
}

} // namespace softbody::gpu

/**
 * @class   vtkSoftBodyObstacleTimeline
 * @brief   The Soft Body filter's Obstacles input over time: which connections the simulation
 *          was built with, the moving ones' surfaces at every time fetched so far, and the
 *          time the next pipeline pass must request them at.
 *
 * A moving obstacle (its producer advertises times) is needed at every frame time the
 * simulation passes, but the pipeline delivers it at one time per pass. So the simulation runs
 * frame by frame as far as the surfaces fetched so far allow; when one is missing it names the
 * time (RequestTime), the filter asks the executive to run again (CONTINUE_EXECUTING),
 * RequestUpdateExtent requests the moving obstacles at that time, and the next pass records
 * them (Record) and resumes. Static obstacles are requested at no time, so they never
 * re-execute, and are set on the simulation once.
 */
#ifndef vtkSoftBodyObstacleTimeline_h
#define vtkSoftBodyObstacleTimeline_h

#include "softbody/collision/obstacle.h"

#include "vtkType.h"

#include <map>
#include <string>
#include <vector>

class vtkInformation;
class vtkInformationVector;
namespace softbody
{
class Simulation;
}

/// One connection of the Obstacles input as far as the frame cache's key is concerned: a
/// static one by its surface (an equal surface from a re-executed source keeps the frames), a
/// moving one by its producer's pipeline modification time (its surfaces change with the
/// requested time, which does not modify the pipeline; a changed source parameter does).
struct vtkSoftBodyObstacleConnection
{
  bool Moving = false;
  vtkMTimeType PipelineMTime = 0;   ///< moving ones only
  softbody::ObstacleSurface Static; ///< static ones only
  bool operator==(const vtkSoftBodyObstacleConnection&) const = default;
};

class vtkSoftBodyObstacleTimeline
{
public:
  /// Reads this pass's Obstacles input (the filter's input port 2): each connection's key,
  /// and every connection's surface as delivered now (empty for static ones). Returns the
  /// error for a connection that is not a dataset; empty otherwise.
  static std::string Read(vtkInformationVector* obstaclesInput,
    std::vector<vtkSoftBodyObstacleConnection>& connections,
    std::vector<softbody::ObstacleSurface>& deliveredNow);

  /// Sets the static connections on a newly built simulation, when no connection moves
  /// (moving ones are set before every frame, SetForInterval). Throws InvalidInputError as
  /// core's setObstacles does.
  static void SetStaticObstacles(const std::vector<vtkSoftBodyObstacleConnection>& connections,
    softbody::Simulation& simulation);

  /// The connections of the simulation now built; forgets every surface fetched for the last.
  void Reset(std::vector<vtkSoftBodyObstacleConnection> connections);

  const std::vector<vtkSoftBodyObstacleConnection>& GetConnections() const
  {
    return this->Connections;
  }

  bool HasMoving() const;

  /// Asks one connection's producer (an information object of input port 2) for the time the
  /// simulation needs next when it moves, and for no time when it is static.
  void RequestTime(vtkInformation* connectionInfo) const;

  /// Keeps the surfaces delivered by this pass (Read's `deliveredNow`) as those at the time
  /// they were requested at; nothing when no connection moves.
  void Record(std::vector<softbody::ObstacleSurface> deliveredNow);

  /// Sets the obstacles for the simulation's step over [t0, t1]: the moving ones at t1 with the
  /// velocity from t0 (both fetched by earlier passes), the static ones as they are. False,
  /// with RequestTime set to the missing time, when a surface is not here yet.
  bool SetForInterval(softbody::Simulation& simulation, double t0, double t1);

  /// The obstacle surfaces at time t, for the skinned Surface's correction: the static ones,
  /// and the moving ones as fetched for t (within `tolerance`; one not fetched is left out).
  std::vector<softbody::ObstacleSurface> At(double t, double tolerance) const;

private:
  /// The Obstacles input as the simulation was built with it (part of the cache key).
  std::vector<vtkSoftBodyObstacleConnection> Connections;
  /// Moving obstacles' surfaces by the time they were requested at (frame times and off-grid
  /// request times), one entry per connection (empty surfaces for static ones). Kept with the
  /// simulation: re-simulating an evicted frame needs the obstacles at its times again.
  std::map<double, std::vector<softbody::ObstacleSurface>> MovingAt;
  /// The time the moving obstacles are requested at in the coming pass.
  double NextRequestTime = 0.0;
};

#endif

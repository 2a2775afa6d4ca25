#include "vtkSoftBodyObstacleTimeline.h"

#include "vtkSoftBodyObstacleInput.h"

#include "vtkDataObject.h"
#include "vtkDemandDrivenPipeline.h"
#include "vtkExecutive.h"
#include "vtkInformation.h"
#include "vtkInformationExecutivePortKey.h"
#include "vtkInformationVector.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "softbody/common/simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

//------------------------------------------------------------------------------
std::string vtkSoftBodyObstacleTimeline::Read(vtkInformationVector* obstaclesInput,
  std::vector<vtkSoftBodyObstacleConnection>& connections,
  std::vector<softbody::ObstacleSurface>& deliveredNow)
{
  const int count = obstaclesInput->GetNumberOfInformationObjects();
  for (int c = 0; c < count; ++c)
  {
    vtkInformation* info = obstaclesInput->GetInformationObject(c);
    vtkDataObject* object = info->Get(vtkDataObject::DATA_OBJECT());
    const std::string typeError = vtkSoftBodyObstacleInput::TypeError(object);
    if (!typeError.empty())
    {
      std::ostringstream message;
      message << "Obstacles input " << c << ": " << typeError;
      return message.str();
    }
    vtkSoftBodyObstacleConnection connection;
    connection.Moving = vtkSoftBodyObstacleInput::IsTemporal(info);
    if (connection.Moving)
    {
      auto* producer =
        vtkDemandDrivenPipeline::SafeDownCast(vtkExecutive::PRODUCER()->GetExecutive(info));
      connection.PipelineMTime = producer ? producer->GetPipelineMTime() : 0;
      deliveredNow.push_back(vtkSoftBodyObstacleInput::ToObstacle(object));
    }
    else
    {
      connection.Static = vtkSoftBodyObstacleInput::ToObstacle(object);
      deliveredNow.emplace_back();
    }
    connections.push_back(std::move(connection));
  }
  return std::string();
}

//------------------------------------------------------------------------------
void vtkSoftBodyObstacleTimeline::SetStaticObstacles(
  const std::vector<vtkSoftBodyObstacleConnection>& connections, softbody::Simulation& simulation)
{
  const bool anyMoving = std::any_of(connections.begin(), connections.end(),
    [](const vtkSoftBodyObstacleConnection& c) { return c.Moving; });
  if (connections.empty() || anyMoving)
  {
    return;
  }
  std::vector<softbody::ObstacleSurface> surfaces;
  for (const vtkSoftBodyObstacleConnection& connection : connections)
  {
    surfaces.push_back(connection.Static);
  }
  simulation.setObstacles(std::move(surfaces), 0.0);
}

//------------------------------------------------------------------------------
void vtkSoftBodyObstacleTimeline::Reset(std::vector<vtkSoftBodyObstacleConnection> connections)
{
  this->Connections = std::move(connections);
  this->MovingAt.clear();
}

//------------------------------------------------------------------------------
bool vtkSoftBodyObstacleTimeline::HasMoving() const
{
  return std::any_of(this->Connections.begin(), this->Connections.end(),
    [](const vtkSoftBodyObstacleConnection& c) { return c.Moving; });
}

//------------------------------------------------------------------------------
void vtkSoftBodyObstacleTimeline::RequestTime(vtkInformation* connectionInfo) const
{
  if (vtkSoftBodyObstacleInput::IsTemporal(connectionInfo))
  {
    connectionInfo->Set(
      vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), this->NextRequestTime);
  }
  else
  {
    connectionInfo->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
}

//------------------------------------------------------------------------------
void vtkSoftBodyObstacleTimeline::Record(std::vector<softbody::ObstacleSurface> deliveredNow)
{
  if (this->HasMoving())
  {
    this->MovingAt[this->NextRequestTime] = std::move(deliveredNow);
  }
}

//------------------------------------------------------------------------------
bool vtkSoftBodyObstacleTimeline::SetForInterval(
  softbody::Simulation& simulation, double t0, double t1)
{
  if (!this->HasMoving())
  {
    return true;
  }
  const auto start = this->MovingAt.find(t0);
  const auto end = this->MovingAt.find(t1);
  if (start == this->MovingAt.end() || end == this->MovingAt.end())
  {
    this->NextRequestTime = start == this->MovingAt.end() ? t0 : t1;
    return false;
  }
  std::vector<softbody::ObstacleSurface> surfaces;
  for (std::size_t c = 0; c < this->Connections.size(); ++c)
  {
    const vtkSoftBodyObstacleConnection& connection = this->Connections[c];
    surfaces.push_back(connection.Moving
        ? vtkSoftBodyObstacleInput::WithVelocities(end->second[c], start->second[c], t1 - t0)
        : connection.Static);
  }
  simulation.setObstacles(std::move(surfaces), t1);
  return true;
}

//------------------------------------------------------------------------------
std::vector<softbody::ObstacleSurface> vtkSoftBodyObstacleTimeline::At(
  double t, double tolerance) const
{
  std::vector<softbody::ObstacleSurface> surfaces;
  // The fetch nearest to t (fetched at frame times k * FrameInterval, which a requested time
  // may differ from by rounding).
  auto moving = this->MovingAt.lower_bound(t - tolerance);
  if (moving != this->MovingAt.end() && std::abs(moving->first - t) > tolerance)
  {
    moving = this->MovingAt.end();
  }
  for (std::size_t c = 0; c < this->Connections.size(); ++c)
  {
    if (!this->Connections[c].Moving)
    {
      surfaces.push_back(this->Connections[c].Static);
    }
    else if (moving != this->MovingAt.end() && c < moving->second.size())
    {
      surfaces.push_back(moving->second[c]);
    }
  }
  return surfaces;
}

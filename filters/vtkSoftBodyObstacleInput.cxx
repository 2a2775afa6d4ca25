#include "vtkSoftBodyObstacleInput.h"

#include "vtkCellArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetSurfaceFilter.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTriangleFilter.h"

//------------------------------------------------------------------------------
std::string vtkSoftBodyObstacleInput::TypeError(vtkDataObject* object)
{
  if (!object || vtkDataSet::SafeDownCast(object))
  {
    return {};
  }
  return std::string("The Obstacles input must be a dataset (a surface or any mesh whose outer "
                     "surface is the obstacle); got a ") +
    object->GetClassName() + ". Extract a block (Extract Block, Merge Blocks) first.";
}

//------------------------------------------------------------------------------
softbody::ObstacleSurface vtkSoftBodyObstacleInput::ToObstacle(vtkDataObject* object)
{
  softbody::ObstacleSurface obstacle;
  vtkDataSet* dataSet = vtkDataSet::SafeDownCast(object);
  if (!dataSet || dataSet->GetNumberOfCells() == 0)
  {
    return obstacle;
  }
  // The outer surface keeps the faces' orientation (a polydata passes through unchanged); the
  // triangle filter splits polygons and strips in order, so each triangle keeps its normal.
  vtkNew<vtkDataSetSurfaceFilter> surface;
  surface->SetInputData(dataSet);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(surface->GetOutputPort());
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  triangles->Update();
  vtkPolyData* mesh = triangles->GetOutput();

  const vtkIdType numPoints = mesh->GetNumberOfPoints();
  obstacle.vertices.resize(static_cast<std::size_t>(numPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    double p[3];
    mesh->GetPoint(i, p);
    obstacle.vertices[static_cast<std::size_t>(i)] = softbody::Vec3(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = mesh->GetPolys();
  obstacle.triangles.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
  vtkIdType count = 0;
  const vtkIdType* ids = nullptr;
  for (polys->InitTraversal(); polys->GetNextCell(count, ids);)
  {
    if (count == 3)
    {
      obstacle.triangles.push_back({ static_cast<std::int32_t>(ids[0]),
        static_cast<std::int32_t>(ids[1]), static_cast<std::int32_t>(ids[2]) });
    }
  }
  return obstacle;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyObstacleInput::IsTemporal(vtkInformation* inputInfo)
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  return inputInfo && (inputInfo->Has(SDDP::TIME_STEPS()) || inputInfo->Has(SDDP::TIME_RANGE()));
}

//------------------------------------------------------------------------------
softbody::ObstacleSurface vtkSoftBodyObstacleInput::WithVelocities(
  softbody::ObstacleSurface end, const softbody::ObstacleSurface& start, double interval)
{
  end.velocities.clear();
  if (interval <= 0.0 || end.vertices.size() != start.vertices.size() ||
    end.triangles != start.triangles)
  {
    return end;
  }
  bool moving = false;
  end.velocities.resize(end.vertices.size());
  for (std::size_t i = 0; i < end.vertices.size(); ++i)
  {
    end.velocities[i] = (end.vertices[i] - start.vertices[i]) / interval;
    moving = moving || end.velocities[i] != softbody::Vec3::Zero();
  }
  if (!moving)
  {
    end.velocities.clear(); // static over this frame: the cheaper contract case
  }
  return end;
}

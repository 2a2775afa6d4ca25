#include "vtkSoftBodySurfaceInput.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCleanPolyData.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObject.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkTriangleFilter.h"

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkSoftBodySurfaceInput::CleanTriangles(vtkPolyData* input)
{
  vtkNew<vtkPolyData> surface;
  surface->ShallowCopy(input);
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(surface);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  vtkNew<vtkCleanPolyData> merge;
  merge->SetInputConnection(triangulate->GetOutputPort());
  merge->ToleranceIsAbsoluteOn();
  merge->SetAbsoluteTolerance(0.0);
  merge->Update();
  vtkSmartPointer<vtkPolyData> triangles = merge->GetOutput();
  return triangles;
}

//------------------------------------------------------------------------------
void vtkSoftBodySurfaceInput::ToCore(vtkPolyData* triangles, std::vector<softbody::Vec3>& points,
  std::vector<std::array<std::int32_t, 3>>& faces)
{
  points.resize(static_cast<std::size_t>(triangles->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < triangles->GetNumberOfPoints(); ++i)
  {
    triangles->GetPoint(i, points[static_cast<std::size_t>(i)].data());
  }
  faces.clear();
  faces.reserve(static_cast<std::size_t>(triangles->GetNumberOfPolys()));
  auto iter = vtk::TakeSmartPointer(triangles->GetPolys()->NewIterator());
  for (iter->GoToFirstCell(); !iter->IsDoneWithTraversal(); iter->GoToNextCell())
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    iter->GetCurrentCell(n, ids);
    if (n == 3)
    {
      faces.push_back({ static_cast<std::int32_t>(ids[0]), static_cast<std::int32_t>(ids[1]),
        static_cast<std::int32_t>(ids[2]) });
    }
  }
}

//------------------------------------------------------------------------------
std::string vtkSoftBodySurfaceInput::SkinSurfaceError(vtkDataObject* surface)
{
  if (!surface || vtkPolyData::SafeDownCast(surface))
  {
    return {};
  }
  std::string remedy = "apply Extract Surface to it first";
  if (vtkCompositeDataSet::SafeDownCast(surface))
  {
    remedy = "apply Merge Blocks, then Extract Surface, to it first";
  }
  return std::string("The Surface input must be a polygonal surface (vtkPolyData); it is a ") +
    surface->GetClassName() + ". To skin it onto the body, " + remedy + ".";
}

#include "vtkSoftBodyArrays.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>

// Copies core's vectors into a new 3-component VTK array. A copy, not zero-copy: the
// simulation overwrites its arrays on the next request while the output may still be in use.
vtkSmartPointer<vtkDoubleArray> vtkSoftBodyArrays::MakeVectorArray(
  const char* name, const std::vector<softbody::Vec3>& values)
{
  static_assert(sizeof(softbody::Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  if (!values.empty())
  {
    const double* first = values.front().data();
    std::copy(first, first + 3 * values.size(), array->GetPointer(0));
  }
  return array;
}

vtkSmartPointer<vtkDoubleArray> vtkSoftBodyArrays::MakeScalarArray(const char* name, const std::vector<double>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

vtkSmartPointer<vtkStringArray> vtkSoftBodyArrays::MakeStringArray(
  const char* name, const std::vector<std::string>& values)
{
  auto array = vtkSmartPointer<vtkStringArray>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  return array;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSoftBodyArrays::ContentMTime(vtkDataSet* data)
{
  if (!data)
  {
    return 0;
  }
  vtkMTimeType latest = 0;
  const auto see = [&](vtkObject* object) {
    if (object)
    {
      latest = std::max(latest, object->GetMTime());
    }
  };
  if (auto* points = vtkPointSet::SafeDownCast(data))
  {
    see(points->GetPoints());
  }
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
  {
    see(grid->GetCells());
    see(grid->GetCellTypesArray());
  }
  if (auto* poly = vtkPolyData::SafeDownCast(data))
  {
    see(poly->GetVerts());
    see(poly->GetLines());
    see(poly->GetPolys());
    see(poly->GetStrips());
  }
  for (vtkFieldData* arrays : { static_cast<vtkFieldData*>(data->GetPointData()),
         static_cast<vtkFieldData*>(data->GetCellData()), data->GetFieldData() })
  {
    for (int i = 0; arrays && i < arrays->GetNumberOfArrays(); ++i)
    {
      see(arrays->GetAbstractArray(i));
    }
  }
  return latest;
}

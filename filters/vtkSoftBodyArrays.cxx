#include "vtkSoftBodyArrays.h"

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

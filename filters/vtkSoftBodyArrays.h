/**
 * @file   vtkSoftBodyArrays.h
 * @brief  Core's arrays as new VTK arrays, for the Soft Body filters' outputs.
 *
 * Copies, not zero-copy: a simulation overwrites its arrays on the next request while an
 * output may still be in use.
 */
#ifndef vtkSoftBodyArrays_h
#define vtkSoftBodyArrays_h

#include "softbody/common/geometry.h"

#include "vtkDoubleArray.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include <string>
#include <vector>

namespace vtkSoftBodyArrays
{
/// A 3-component array, one tuple per vector.
vtkSmartPointer<vtkDoubleArray> MakeVectorArray(const char* name, const std::vector<softbody::Vec3>& values);
/// A 1-component array.
vtkSmartPointer<vtkDoubleArray> MakeScalarArray(const char* name, const std::vector<double>& values);
/// A string array (field data: plan, warnings, names).
vtkSmartPointer<vtkStringArray> MakeStringArray(const char* name, const std::vector<std::string>& values);
}

#endif

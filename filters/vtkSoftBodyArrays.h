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
#include "vtkType.h"

class vtkDataSet;

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

/// When `data`'s content last changed: the latest modification of its points, cells and
/// arrays (0 for null). Unlike the data object's own MTime it does not move when a pipeline
/// shallow-copies the same content into it again (a source consumed by two filters with
/// different requests re-executes so), which would otherwise rebuild the simulation.
vtkMTimeType ContentMTime(vtkDataSet* data);
}

#endif

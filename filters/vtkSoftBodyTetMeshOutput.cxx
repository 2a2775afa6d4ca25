#include "vtkSoftBodyTetMeshOutput.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"

#include <algorithm>
#include <exception>

void vtkSoftBodyTetMeshOutput::Fill(const softbody::TetMesh& mesh, vtkUnstructuredGrid* output)
{
  output->Initialize();
  static_assert(sizeof(softbody::Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
  vtkNew<vtkDoubleArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
  if (!mesh.points.empty())
  {
    const double* first = mesh.points.front().data();
    std::copy(first, first + 3 * mesh.points.size(), xyz->GetPointer(0));
  }
  vtkNew<vtkPoints> points;
  points->SetData(xyz);

  // Offsets/connectivity arrays built directly: one pass, no per-cell InsertNextCell.
  const auto nTets = static_cast<vtkIdType>(mesh.tets.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nTets + 1);
  connectivity->SetNumberOfValues(4 * nTets);
  for (vtkIdType t = 0; t <= nTets; ++t)
  {
    offsets->SetValue(t, 4 * t);
  }
  for (vtkIdType t = 0; t < nTets; ++t)
  {
    for (int c = 0; c < 4; ++c)
    {
      connectivity->SetValue(4 * t + c, mesh.tets[static_cast<std::size_t>(t)][c]);
    }
  }
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(nTets);
  types->FillValue(VTK_TETRA);

  output->SetPoints(points);
  output->SetCells(types, cells);
}

//------------------------------------------------------------------------------
int vtkSoftBodyTetMeshOutput::ReadFile(vtkAlgorithm* reader, const std::string& fileName,
  Loader load, vtkUnstructuredGrid* output)
{
  if (!output)
  {
    vtkErrorWithObjectMacro(reader, "Missing output data object.");
    return 0;
  }
  if (fileName.empty())
  {
    vtkErrorWithObjectMacro(reader, "No FileName given.");
    return 0;
  }
  reader->UpdateProgress(0.0);
  softbody::TetMesh mesh;
  softbody::MeshFileInfo info;
  try
  {
    mesh = load(fileName, &info);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorWithObjectMacro(reader, << e.what());
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorWithObjectMacro(reader, << "Cannot read '" << fileName << "': " << e.what());
    return 0;
  }
  // What the reader changed (e.g. hexahedra split into tets): said, not done silently.
  for (const std::string& warning : info.warnings)
  {
    vtkWarningWithObjectMacro(reader, << warning);
  }
  Fill(mesh, output);
  vtkNew<vtkIdTypeArray> skipped;
  skipped->SetName("SkippedElements");
  skipped->InsertNextValue(static_cast<vtkIdType>(info.skippedElements));
  output->GetFieldData()->AddArray(skipped);
  AddGroups(info, output);
  reader->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkSoftBodyTetMeshOutput::AddGroups(const softbody::MeshFileInfo& info, vtkUnstructuredGrid* output)
{
  const auto cellArray = [&](const char* name, const std::vector<long long>& tags) {
    if (static_cast<vtkIdType>(tags.size()) != output->GetNumberOfCells())
    {
      return;
    }
    vtkNew<vtkIdTypeArray> array;
    array->SetName(name);
    array->SetNumberOfValues(static_cast<vtkIdType>(tags.size()));
    for (std::size_t c = 0; c < tags.size(); ++c)
    {
      array->SetValue(static_cast<vtkIdType>(c), static_cast<vtkIdType>(tags[c]));
    }
    output->GetCellData()->AddArray(array);
  };
  cellArray("GmshPhysical", info.tetPhysicalTag);
  cellArray("GmshEntity", info.tetEntityTag);
  // Each physical group as a point array named after it (1 on its nodes): a Soft Body
  // Condition's Selection Array, or a Pinned Points Array, as it is.
  for (const softbody::MeshGroup& group : info.groups)
  {
    std::string name = group.name;
    if (output->GetPointData()->GetArray(name.c_str()))
    {
      name += " (" + std::to_string(group.dimension) + "D)"; // the same name in two dimensions
    }
    vtkNew<vtkUnsignedCharArray> flags;
    flags->SetName(name.c_str());
    flags->SetNumberOfValues(static_cast<vtkIdType>(group.points.size()));
    for (std::size_t i = 0; i < group.points.size(); ++i)
    {
      flags->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(group.points[i]));
    }
    output->GetPointData()->AddArray(flags);
  }
}

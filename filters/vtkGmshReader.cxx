#include "vtkGmshReader.h"

#include "vtkSoftBodyTetMeshOutput.h"

#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/errors.h"
#include "softbody/mesh_io.h"

vtkStandardNewMacro(vtkGmshReader);

//------------------------------------------------------------------------------
vtkGmshReader::vtkGmshReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
int vtkGmshReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!output)
  {
    vtkErrorMacro("Missing output data object.");
    return 0;
  }
  if (this->FileName.empty())
  {
    vtkErrorMacro("No FileName given.");
    return 0;
  }
  this->UpdateProgress(0.0);
  softbody::TetMesh mesh;
  softbody::MeshFileInfo info;
  try
  {
    mesh = softbody::readGmshMesh(this->FileName, &info);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Cannot read '" << this->FileName << "': " << e.what());
    return 0;
  }
  vtkSoftBodyTetMeshOutput::Fill(mesh, output);
  vtkNew<vtkIdTypeArray> skipped;
  skipped->SetName("SkippedElements");
  skipped->InsertNextValue(static_cast<vtkIdType>(info.skippedElements));
  output->GetFieldData()->AddArray(skipped);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkGmshReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

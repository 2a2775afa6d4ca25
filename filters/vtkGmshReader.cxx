#include "vtkGmshReader.h"

#include "vtkSoftBodyTetMeshOutput.h"

#include "vtkObjectFactory.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/mesh/mesh_io.h"

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
  // Overload resolution picks the path-taking loader.
  softbody::TetMesh (*load)(const std::string&, softbody::MeshFileInfo*) = softbody::readGmshMesh;
  return vtkSoftBodyTetMeshOutput::ReadFile(
    this, this->FileName, load, vtkUnstructuredGrid::GetData(outputVector, 0));
}

//------------------------------------------------------------------------------
void vtkGmshReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

#include "vtkTetGenReader.h"

#include "vtkSoftBodyTetMeshOutput.h"

#include "vtkObjectFactory.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/mesh/mesh_io.h"

vtkStandardNewMacro(vtkTetGenReader);

//------------------------------------------------------------------------------
vtkTetGenReader::vtkTetGenReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
int vtkTetGenReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // Overload resolution picks the path-taking loader.
  softbody::TetMesh (*load)(const std::string&, softbody::MeshFileInfo*) = softbody::readTetGenMesh;
  return vtkSoftBodyTetMeshOutput::ReadFile(
    this, this->FileName, load, vtkUnstructuredGrid::GetData(outputVector, 0));
}

//------------------------------------------------------------------------------
void vtkTetGenReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

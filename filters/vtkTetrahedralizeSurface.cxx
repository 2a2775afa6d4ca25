#include "vtkTetrahedralizeSurface.h"
#include "vtkSoftBodySurfaceInput.h"

#include "vtkSoftBodyTetMeshOutput.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkTriangleFilter.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/mesh/tetrahedralize.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkTetrahedralizeSurface);

//------------------------------------------------------------------------------
vtkTetrahedralizeSurface::vtkTetrahedralizeSurface()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
int vtkTetrahedralizeSurface::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port != 0)
  {
    return 0;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkTetrahedralizeSurface::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Fetch info and downcast.
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro("Missing input or output data object.");
    return 0;
  }
  if (input->GetNumberOfPoints() == 0 || input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    vtkErrorMacro("The input has no polygons: Tetrahedralize Surface needs a closed triangle "
                  "surface (e.g. from an OBJ, STL or PLY file).");
    return 0;
  }
  // Refused with the value given (the setters do not clamp).
  try
  {
    softbody::check::nonNegative("MaxRadiusEdgeRatio", this->MaxRadiusEdgeRatio, "", "no refinement");
    softbody::check::inRange("MinDihedralAngle", this->MinDihedralAngle, 0.0, 70.0);
    softbody::check::nonNegative("MaxTetVolume", this->MaxTetVolume, "", "unbounded");
    softbody::check::atLeast("MaxAddedPoints", this->MaxAddedPoints, 0);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  this->UpdateProgress(0.0);

  // Triangulate polygons and strips and merge coincident points (OBJ triangle soups).
  vtkSmartPointer<vtkPolyData> triangles = vtkSoftBodySurfaceInput::CleanTriangles(input);
  this->UpdateProgress(0.05);
  std::vector<softbody::Vec3> points;
  std::vector<std::array<std::int32_t, 3>> faces;
  vtkSoftBodySurfaceInput::ToCore(triangles, points, faces);

  softbody::TetrahedralizeOptions options;
  options.maxRadiusEdgeRatio = this->MaxRadiusEdgeRatio;
  options.minDihedralAngle = this->MinDihedralAngle;
  options.preserveBoundary = this->PreserveBoundary != 0;
  options.maxAddedPoints = static_cast<std::size_t>(std::max(0, this->MaxAddedPoints));
  options.quiet = true;
  options.maxTetVolume = this->MaxTetVolume;
  if (this->MaxTetVolumeIsRelative && this->MaxTetVolume > 0.0)
  {
    double b[6];
    triangles->GetBounds(b);
    const double boxVolume = (b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]);
    if (!(boxVolume > 0.0) || !std::isfinite(boxVolume))
    {
      vtkErrorMacro("The input is flat (its bounding box has no volume): it encloses nothing "
                    "to tetrahedralize.");
      return 0;
    }
    options.maxTetVolume = this->MaxTetVolume * boxVolume;
  }

  // TetGen runs in one uninterruptible call: honor an abort request before it.
  if (this->CheckAbort())
  {
    return 1;
  }
  softbody::TetMesh mesh;
  softbody::TetrahedralizeStats stats;
  try
  {
    mesh = softbody::tetrahedralizeSurface(points, faces, options, &stats);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Tetrahedralization failed: " << e.what());
    return 0;
  }
  this->UpdateProgress(0.95);
  if (stats.addedPointsLimitReached)
  {
    vtkWarningMacro(<< "TetGen stopped at MaxAddedPoints (" << this->MaxAddedPoints
                    << " added points): the quality and volume bounds may not be met everywhere. "
                       "Relax MaxRadiusEdgeRatio / MinDihedralAngle or raise MaxAddedPoints.");
  }

  // Assemble the output.
  vtkSoftBodyTetMeshOutput::Fill(mesh, output);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkTetrahedralizeSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaxRadiusEdgeRatio: " << this->MaxRadiusEdgeRatio << "\n";
  os << indent << "MinDihedralAngle: " << this->MinDihedralAngle << "\n";
  os << indent << "MaxTetVolume: " << this->MaxTetVolume << "\n";
  os << indent << "MaxTetVolumeIsRelative: " << this->MaxTetVolumeIsRelative << "\n";
  os << indent << "PreserveBoundary: " << this->PreserveBoundary << "\n";
  os << indent << "MaxAddedPoints: " << this->MaxAddedPoints << "\n";
}

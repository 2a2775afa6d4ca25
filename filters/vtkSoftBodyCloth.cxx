#include "vtkSoftBodyCloth.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/pbd/cloth.h"
#include "softbody/common/errors.h"

vtkStandardNewMacro(vtkSoftBodyCloth);

//------------------------------------------------------------------------------
vtkSoftBodyCloth::vtkSoftBodyCloth()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
int vtkSoftBodyCloth::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  // Refused with the value given (the setters do not clamp).
  try
  {
    softbody::check::positive("TotalMass", this->TotalMass, "kg");
    softbody::check::nonNegative("DiagonalStiffness", this->DiagonalStiffness, "", "no diagonals");
    softbody::check::atLeast("Resolution[0]", this->Resolution[0], 2);
    softbody::check::atLeast("Resolution[1]", this->Resolution[1], 2);
    if (this->PinnedCorners < NO_CORNERS || this->PinnedCorners > ALL_CORNERS)
    {
      softbody::check::badChoice("PinnedCorners", this->PinnedCorners, "0 (none), 1 (Point2 edge), 2 (all)");
    }
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  softbody::ClothSpec spec;
  spec.origin = { this->Origin[0], this->Origin[1], this->Origin[2] };
  spec.point1 = { this->Point1[0], this->Point1[1], this->Point1[2] };
  spec.point2 = { this->Point2[0], this->Point2[1], this->Point2[2] };
  spec.particlesAlong1 = this->Resolution[0];
  spec.particlesAlong2 = this->Resolution[1];
  spec.totalMass = this->TotalMass;
  spec.diagonalStiffness = this->DiagonalStiffness;
  spec.pins = this->PinnedCorners == ALL_CORNERS ? softbody::ClothPins::AllCorners
    : this->PinnedCorners == POINT2_CORNERS      ? softbody::ClothPins::Point2Corners
                                                 : softbody::ClothPins::None;
  if (static_cast<double>(spec.particlesAlong1) * spec.particlesAlong2 > 1e8)
  {
    vtkErrorMacro("Resolution " << spec.particlesAlong1 << " x " << spec.particlesAlong2
                                << " is over 10^8 particles; choose a smaller one.");
    return 0;
  }
  softbody::Body body;
  try
  {
    body = softbody::makeCloth(spec);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(body.mesh.points.size()));
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    points->SetPoint(static_cast<vtkIdType>(i), body.mesh.points[i].data());
  }
  output->SetPoints(points);

  const int nx = spec.particlesAlong1;
  const int ny = spec.particlesAlong2;
  const vtkIdType quads = vtkIdType(nx - 1) * (ny - 1);
  output->AllocateExact(static_cast<vtkIdType>(body.links.size()) + quads, 2 * body.links.size() + 4 * quads);
  auto scale = vtkSmartPointer<vtkDoubleArray>::New();
  scale->SetName("LinkStiffnessScale");
  for (std::size_t j = 0; j < body.links.size(); ++j)
  {
    const vtkIdType ends[2] = { body.links[j][0], body.links[j][1] };
    output->InsertNextCell(VTK_LINE, 2, ends);
    scale->InsertNextValue(body.linkStiffnessScale[j]);
  }
  for (int j = 0; j + 1 < ny; ++j)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      const vtkIdType corner = vtkIdType(j) * nx + i;
      const vtkIdType quad[4] = { corner, corner + 1, corner + 1 + nx, corner + nx };
      output->InsertNextCell(VTK_QUAD, 4, quad);
      scale->InsertNextValue(0.0);
    }
  }
  output->GetCellData()->AddArray(scale);

  auto mass = vtkSmartPointer<vtkDoubleArray>::New();
  mass->SetName("Mass");
  auto pinned = vtkSmartPointer<vtkUnsignedCharArray>::New();
  pinned->SetName("Pinned");
  for (std::size_t i = 0; i < body.mesh.points.size(); ++i)
  {
    mass->InsertNextValue(body.pointMass[i]);
    pinned->InsertNextValue(static_cast<unsigned char>(body.pinned[i]));
  }
  output->GetPointData()->AddArray(mass);
  output->GetPointData()->AddArray(pinned);
  return 1;
}

//------------------------------------------------------------------------------
void vtkSoftBodyCloth::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Origin: " << this->Origin[0] << " " << this->Origin[1] << " " << this->Origin[2] << "\n";
  os << indent << "Point1: " << this->Point1[0] << " " << this->Point1[1] << " " << this->Point1[2] << "\n";
  os << indent << "Point2: " << this->Point2[0] << " " << this->Point2[1] << " " << this->Point2[2] << "\n";
  os << indent << "Resolution: " << this->Resolution[0] << " " << this->Resolution[1] << "\n";
  os << indent << "TotalMass: " << this->TotalMass << "\n";
  os << indent << "DiagonalStiffness: " << this->DiagonalStiffness << "\n";
  os << indent << "PinnedCorners: " << this->PinnedCorners << "\n";
}

#include "vtkSoftBodyMethodChoice.h"

#include "vtkSoftBodyParameters.h"

#include "vtkCellType.h"
#include "vtkCommunicator.h"
#include "vtkDataSet.h"
#include "vtkMultiProcessController.h"

#include <string>

//------------------------------------------------------------------------------
int vtkSoftBodyMethodChoice::Resolve(
  int method, vtkDataSet* input, vtkMultiProcessController* controller, std::string& note)
{
  note.clear();
  if (method != vtkSoftBodyParameters::METHOD_AUTOMATIC)
  {
    return method; // chosen by the user (an out-of-range value is refused with the others)
  }
  // How many links (line cells) and tets the body has, over every rank.
  double counts[2] = { 0.0, 0.0 };
  const vtkIdType cells = input ? input->GetNumberOfCells() : 0;
  for (vtkIdType c = 0; c < cells; ++c)
  {
    const int type = input->GetCellType(c);
    counts[0] += type == VTK_LINE || type == VTK_POLY_LINE ? 1.0 : 0.0;
    counts[1] += type == VTK_TETRA ? 1.0 : 0.0;
  }
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    double everywhere[2] = { 0.0, 0.0 };
    controller->AllReduce(counts, everywhere, 2, vtkCommunicator::SUM_OP);
    counts[0] = everywhere[0];
    counts[1] = everywhere[1];
  }
  if (counts[0] == 0.0)
  {
    // Tets, or cells no method takes: Mass-Spring, whose refusal names the remedy.
    return vtkSoftBodyParameters::MASS_SPRING;
  }
  note = "Method Automatic chose XPBD: the body has " + std::to_string(static_cast<long long>(counts[0])) +
    " links (line cells, as Soft Body Voxelize and Soft Body Cloth make)" +
    (counts[1] > 0.0 ? " beside " + std::to_string(static_cast<long long>(counts[1])) + " tets" : std::string()) +
    ", which Mass-Spring does not simulate. Set Method to XPBD to tune its properties, or to PBD.";
  return vtkSoftBodyParameters::XPBD;
}

//------------------------------------------------------------------------------
const char* vtkSoftBodyMethodChoice::Name(int method)
{
  switch (method)
  {
    case vtkSoftBodyParameters::MASS_SPRING:
      return "Mass-Spring";
    case vtkSoftBodyParameters::PBD:
      return "PBD";
    case vtkSoftBodyParameters::XPBD:
      return "XPBD";
    default:
      return "Automatic";
  }
}

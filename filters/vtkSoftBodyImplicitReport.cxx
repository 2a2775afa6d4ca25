#include "vtkSoftBodyImplicitReport.h"

#include "softbody/mesh/reorder.h"
#include "softbody/massspring/contact_planes.h"
#include "softbody/massspring/mass_spring_simulation.h"

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkTable.h>

#include <sstream>

//------------------------------------------------------------------------------
void vtkSoftBodyImplicitReport::AddFields(
  const softbody::ImplicitConvergence& c, vtkFieldData* field)
{
  vtkNew<vtkIntArray> iterations;
  iterations->SetName("Iterations");
  iterations->InsertNextValue(c.iterations);
  field->AddArray(iterations);
  vtkNew<vtkDoubleArray> residual;
  residual->SetName("Residual");
  residual->InsertNextValue(c.residual);
  field->AddArray(residual);
  vtkNew<vtkIdTypeArray> unconverged;
  unconverged->SetName("UnconvergedSteps");
  unconverged->InsertNextValue(static_cast<vtkIdType>(c.unconvergedSteps));
  field->AddArray(unconverged);
  vtkNew<vtkIdTypeArray> linear;
  linear->SetName("LinearIterations");
  linear->InsertNextValue(static_cast<vtkIdType>(c.linearIterationsTotal));
  field->AddArray(linear);
  // The automatic steps split where a contact came too fast for one (contactPieces), and the
  // steps they became.
  vtkNew<vtkIdTypeArray> split;
  split->SetName("ContactSplitSteps");
  split->SetNumberOfComponents(2);
  split->SetComponentName(0, "Split");
  split->SetComponentName(1, "Into");
  split->InsertNextTuple2(static_cast<double>(c.contactSplitSteps), static_cast<double>(c.contactSplitPieces));
  field->AddArray(split);
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyImplicitReport::ContactWarning(
  const softbody::ImplicitConvergence& c, const char* integrator)
{
  if (c.fastContactSteps == 0)
  {
    return {};
  }
  std::ostringstream message;
  message << c.fastContactSteps << " " << integrator
          << " steps reached a contact faster than its elements: in one step of "
          << c.fastestApproachStep << " s a point moved " << c.fastestApproach
          << " m into the floor, an obstacle or another body, against elements of " << c.fastestApproachSize
          << " m. The step stops it there while the points above it move on, which crushes or "
             "inverts the elements at the contact: take a TimeStep of at most "
          << c.fastestApproachStep * softbody::kContactApproachFraction * c.fastestApproachSize / c.fastestApproach
          << " s, or TimeStep 0 (automatic), which splits such steps.";
  return message.str();
}

//------------------------------------------------------------------------------
void vtkSoftBodyImplicitReport::FillTable(
  const softbody::ImplicitConvergence& c, vtkTable* output)
{
  vtkNew<vtkIntArray> iteration;
  iteration->SetName("Iteration");
  vtkNew<vtkDoubleArray> residual;
  residual->SetName("Residual");
  for (std::size_t k = 0; k < c.residualHistory.size(); ++k)
  {
    iteration->InsertNextValue(static_cast<int>(k));
    residual->InsertNextValue(c.residualHistory[k]);
  }
  output->AddColumn(iteration);
  output->AddColumn(residual);
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyImplicitReport::Warning(
  const softbody::ImplicitConvergence& c, const char* integrator, int maxIterations)
{
  if (c.unconvergedSteps == 0)
  {
    return {};
  }
  std::ostringstream message;
  message << c.unconvergedSteps << " of " << c.steps << " " << integrator
          << " steps did not converge: they ended above ImplicitTolerance (last residual "
          << c.residual << "), stopped at ImplicitMaxIterations = " << maxIterations
          << " or where no step length lowered the energy any further (the precision floor of a "
             "stiff body). Those steps are not accurate. Raise ImplicitMaxIterations";
  if (std::string(integrator) == "Projective Dynamics" || std::string(integrator) == "Vertex Block Descent")
  {
    message << ", or use Implicit Euler, whose Newton iterations handle stiff materials "
               "(" << integrator << " converges slowly on them)";
  }
  else
  {
    message << " or take smaller steps (TimeStep)";
  }
  message << ".";
  return message.str();
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyImplicitReport::LandingWarning(const softbody::Simulation& simulation, double step)
{
  const softbody::Simulation* inner = &simulation;
  if (const auto* reordered = dynamic_cast<const softbody::ReorderedSimulation*>(inner))
  {
    inner = &reordered->inner(); // the estimate reads no point by index
  }
  const auto* massSpring = dynamic_cast<const softbody::MassSpringSimulation*>(inner);
  return massSpring ? massSpring->landingStepWarning(step) : std::string();
}

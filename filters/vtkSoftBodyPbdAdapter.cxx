#include "vtkSoftBodyPbdAdapter.h"

#include "vtkSoftBodySettings.h"
#include "vtkSoftBodyInputConversion.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>

//------------------------------------------------------------------------------
std::unique_ptr<softbody::Simulation> vtkSoftBodyPbdAdapter::Create(
  const vtkSoftBodyCoreSettings& coreSettings, vtkUnstructuredGrid* input, std::string& error,
  softbody::PbdSimulation*& solver)
{
  softbody::Body body;
  error = vtkSoftBodyInputConversion::ConvertParticles(
    input, coreSettings.PinnedPointsArray, body, this->TetCells, this->LinkCells);
  if (!error.empty())
  {
    return nullptr;
  }
  body.conditions = coreSettings.Conditions;
  body.material = coreSettings.Material;
  // The arrays have a value per input cell; core reads one per tet, and the input may mix tets
  // with the line and vertex cells of links and particles.
  softbody::CellMaterial perCell;
  error = vtkSoftBodyInputConversion::ConvertCellMaterial(input, coreSettings.YoungsModulusArray,
    coreSettings.PoissonRatioArray, coreSettings.DensityArray, perCell);
  if (!error.empty())
  {
    return nullptr;
  }
  const auto perTet = [this](const std::vector<double>& values) {
    std::vector<double> tets;
    if (!values.empty())
    {
      tets.reserve(this->TetCells.size());
      for (vtkIdType cell : this->TetCells)
      {
        tets.push_back(values[static_cast<std::size_t>(cell)]);
      }
    }
    return tets;
  };
  body.material.cells = { perTet(perCell.youngsModulus), perTet(perCell.poissonRatio),
    perTet(perCell.density) };
  softbody::PbdSettings settings = coreSettings.Pbd;
  // A Soft Body Voxelize lattice says how large its particles are: they then rest on the floor
  // with their surface, not their center.
  if (vtkDataArray* radius = input->GetFieldData()->GetArray("ParticleRadius"))
  {
    if (radius->GetNumberOfTuples() > 0 && radius->GetTuple1(0) >= 0.0)
    {
      settings.particleRadius = radius->GetTuple1(0);
    }
  }
  return softbody::makePbdSimulation(
    std::move(body), settings, softbody::kDefaultVertexOrdering, &solver);
}

//------------------------------------------------------------------------------
void vtkSoftBodyPbdAdapter::AddBrokenCells(
  const softbody::PbdSimulation& simulation, vtkUnstructuredGrid* output) const
{
  const vtkIdType numCells = output->GetNumberOfCells();
  auto broken = vtkSmartPointer<vtkUnsignedCharArray>::New();
  broken->SetName("Broken");
  broken->SetNumberOfValues(numCells);
  broken->FillValue(0);
  for (std::size_t k = 0; k < this->TetCells.size() && k < simulation.volumes().size(); ++k)
  {
    if (simulation.tetBroken(k))
    {
      broken->SetValue(this->TetCells[k], 1);
    }
  }
  const std::size_t offset = simulation.explicitLinkOffset();
  for (std::size_t j = 0; j < this->LinkCells.size(); ++j)
  {
    if (simulation.linkBroken(offset + j))
    {
      broken->SetValue(this->LinkCells[j], 1);
    }
  }
  output->GetCellData()->AddArray(broken);
  if (simulation.brokenLinkCount() == 0)
  {
    return;
  }
  // Hidden cells are skipped by ParaView's surface extraction, so the pieces render apart;
  // the cells stay in the output, so cell arrays still map one to one onto the input.
  auto ghosts = vtkSmartPointer<vtkUnsignedCharArray>::New();
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfValues(numCells);
  vtkUnsignedCharArray* inputGhosts = output->GetCellGhostArray();
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const unsigned char given = inputGhosts ? inputGhosts->GetValue(c) : 0;
    ghosts->SetValue(c, broken->GetValue(c) ? static_cast<unsigned char>(given | vtkDataSetAttributes::HIDDENCELL) : given);
  }
  output->GetCellData()->AddArray(ghosts);
}

//------------------------------------------------------------------------------
std::vector<double> vtkSoftBodyPbdAdapter::PerInputCell(
  const std::vector<double>& perTet, vtkIdType numCells) const
{
  std::vector<double> perCell(static_cast<std::size_t>(numCells), std::nan(""));
  for (std::size_t k = 0; k < this->TetCells.size() && k < perTet.size(); ++k)
  {
    perCell[static_cast<std::size_t>(this->TetCells[k])] = perTet[k];
  }
  return perCell;
}

//------------------------------------------------------------------------------
void vtkSoftBodyPbdAdapter::AddConvergenceFields(
  const softbody::PbdSimulation& simulation, vtkUnstructuredGrid* output)
{
  auto iterations = vtkSmartPointer<vtkIntArray>::New();
  iterations->SetName("Iterations");
  iterations->InsertNextValue(simulation.convergence().iterations);
  output->GetFieldData()->AddArray(iterations);
  auto residual = vtkSmartPointer<vtkDoubleArray>::New();
  residual->SetName("Residual");
  residual->InsertNextValue(simulation.convergence().residual);
  output->GetFieldData()->AddArray(residual);
}

//------------------------------------------------------------------------------
void vtkSoftBodyPbdAdapter::FillConvergenceTable(
  const softbody::PbdSimulation& simulation, vtkTable* output)
{
  const std::vector<double>& history = simulation.convergence().residualHistory;
  auto iteration = vtkSmartPointer<vtkIntArray>::New();
  iteration->SetName("Iteration");
  auto residual = vtkSmartPointer<vtkDoubleArray>::New();
  residual->SetName("Residual");
  for (std::size_t k = 0; k < history.size(); ++k)
  {
    iteration->InsertNextValue(static_cast<int>(k + 1));
    residual->InsertNextValue(history[k]);
  }
  output->AddColumn(iteration);
  output->AddColumn(residual);
}

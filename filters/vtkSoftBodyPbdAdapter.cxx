#include "vtkSoftBodyPbdAdapter.h"

#include "vtkSoftBodyFilter.h"
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

namespace
{
softbody::Vec3 ToVec3(const double v[3])
{
  return { v[0], v[1], v[2] };
}

softbody::PbdSettings MakeSettings(vtkSoftBodyFilter& f)
{
  softbody::PbdSettings s;
  s.formulation = f.GetMethod() == vtkSoftBodyFilter::XPBD ? softbody::PbdFormulation::Xpbd
                                                           : softbody::PbdFormulation::Pbd;
  switch (f.GetSolver())
  {
    case vtkSoftBodyFilter::JACOBI:
      s.solver = softbody::PbdSolver::Jacobi;
      break;
    case vtkSoftBodyFilter::PARALLEL_GAUSS_SEIDEL:
      s.solver = softbody::PbdSolver::ParallelGaussSeidel;
      break;
    default:
      s.solver = softbody::PbdSolver::GaussSeidel;
  }
  s.prediction = f.GetIntegrator() == vtkSoftBodyFilter::VERLET ? softbody::PbdPrediction::Verlet
                                                                : softbody::PbdPrediction::SymplecticEuler;
  s.timeStep = f.GetTimeStep();
  s.substeps = f.GetSubsteps();
  s.iterations = f.GetIterations();
  s.residualTolerance = f.GetResidualTolerance();
  s.relaxation = f.GetRelaxation();
  double gravity[3], origin[3], normal[3];
  f.GetGravity(gravity);
  f.GetFloorOrigin(origin);
  f.GetFloorNormal(normal);
  s.gravity = ToVec3(gravity);
  s.damping = f.GetVelocityDamping();
  s.floorEnabled = f.GetFloor() != 0;
  s.floor.origin = ToVec3(origin);
  s.floor.normal = ToVec3(normal);
  s.friction = f.GetFriction();
  s.restitution = f.GetRestitution();
  s.links = { f.GetPBDLinkStiffness(), f.GetXPBDLinkCompliance() };
  s.volumes = { f.GetPBDVolumeStiffness(), f.GetXPBDVolumeCompliance() };
  s.attachments = { f.GetPBDPinStiffness(), f.GetXPBDPinCompliance() };
  s.elasticity.enabled = f.GetXPBDMaterial() == vtkSoftBodyFilter::XPBD_YOUNGS_MODULUS;
  s.elasticity.youngsModulus = f.GetYoungsModulus();
  s.elasticity.poissonRatio = f.GetPoissonRatio();
  s.breakingStrain = f.GetBreakingStrain();
  s.plasticYield = f.GetPlasticYield();
  s.plasticCreep = f.GetPlasticCreep();
  s.invertedTets = f.GetInvertedTets() == vtkSoftBodyFilter::REFUSE
    ? softbody::InvertedTetPolicy::Refuse
    : softbody::InvertedTetPolicy::Reorient;
  return s;
}
} // namespace

//------------------------------------------------------------------------------
std::unique_ptr<softbody::PbdSimulation> vtkSoftBodyPbdAdapter::Create(vtkSoftBodyFilter& filter,
  vtkUnstructuredGrid* input, const std::string& pinnedArrayName, std::string& error)
{
  const int integrator = filter.GetIntegrator();
  if (integrator != vtkSoftBodyFilter::EULER_CROMER && integrator != vtkSoftBodyFilter::VERLET)
  {
    error = "PBD and XPBD predict positions with Euler-Cromer (symplectic Euler) or Verlet; "
            "choose one of those as the Integrator.";
    return nullptr;
  }
  softbody::PbdBody body;
  error = vtkSoftBodyInputConversion::ConvertParticles(input, pinnedArrayName, body, this->TetCells, this->LinkCells);
  if (!error.empty())
  {
    return nullptr;
  }
  body.density = filter.GetDensity();
  body.massDistribution = filter.GetMassDistribution() == vtkSoftBodyFilter::LUMPED_VOLUME
    ? softbody::MassDistribution::LumpedVolume
    : softbody::MassDistribution::AverageIncidentVolume;
  softbody::PbdSettings settings = MakeSettings(filter);
  // A Soft Body Voxelize lattice says how large its particles are: they then rest on the floor
  // with their surface, not their center.
  if (vtkDataArray* radius = input->GetFieldData()->GetArray("ParticleRadius"))
  {
    if (radius->GetNumberOfTuples() > 0 && radius->GetTuple1(0) >= 0.0)
    {
      settings.particleRadius = radius->GetTuple1(0);
    }
  }
  return std::make_unique<softbody::PbdSimulation>(std::move(body), settings);
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

#include "vtkSoftBodyDistribution.h"

#include "vtkAppendFilter.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkIdList.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkThreshold.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/mesh/components.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace
{
constexpr int kBodiesTag = 8607;
constexpr const char* kRankArray = "vtkSoftBodyRank"; // the rank each cell is dealt to

/// The connected components of a grid's cells (cells sharing a point are one body).
softbody::Components BodiesOf(vtkUnstructuredGrid* grid)
{
  std::vector<std::int64_t> offsets{ 0 };
  std::vector<std::int64_t> points;
  vtkNew<vtkIdList> cellPoints;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, cellPoints);
    for (vtkIdType k = 0; k < cellPoints->GetNumberOfIds(); ++k)
    {
      points.push_back(cellPoints->GetId(k));
    }
    offsets.push_back(static_cast<std::int64_t>(points.size()));
  }
  return softbody::connectedComponents(static_cast<std::size_t>(grid->GetNumberOfPoints()), offsets, points);
}

/// The piece without the cells that are ghosts (copies of another rank's cells).
vtkSmartPointer<vtkUnstructuredGrid> OwnedCells(vtkUnstructuredGrid* piece)
{
  auto owned = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkUnsignedCharArray* ghosts = piece->GetCellGhostArray();
  if (!ghosts)
  {
    owned->ShallowCopy(piece);
    return owned;
  }
  vtkNew<vtkIntArray> keep;
  keep->SetName("vtkSoftBodyOwned");
  keep->SetNumberOfValues(piece->GetNumberOfCells());
  for (vtkIdType c = 0; c < piece->GetNumberOfCells(); ++c)
  {
    keep->SetValue(c, (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL) ? 0 : 1);
  }
  auto marked = vtkSmartPointer<vtkUnstructuredGrid>::New();
  marked->ShallowCopy(piece);
  marked->GetCellData()->AddArray(keep);
  vtkNew<vtkThreshold> threshold;
  threshold->SetInputData(marked);
  threshold->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "vtkSoftBodyOwned");
  threshold->SetLowerThreshold(1.0);
  threshold->SetUpperThreshold(1.0);
  threshold->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  threshold->Update();
  owned->ShallowCopy(threshold->GetOutput());
  owned->GetCellData()->RemoveArray("vtkSoftBodyOwned");
  owned->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  owned->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  return owned;
}

/// The cells of `bodies` whose rank array equals `rank`, without the helper arrays.
vtkSmartPointer<vtkUnstructuredGrid> CellsOfRank(vtkUnstructuredGrid* bodies, int rank)
{
  vtkNew<vtkThreshold> threshold;
  threshold->SetInputData(bodies);
  threshold->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, kRankArray);
  threshold->SetLowerThreshold(rank);
  threshold->SetUpperThreshold(rank);
  threshold->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  threshold->Update();
  auto cells = vtkSmartPointer<vtkUnstructuredGrid>::New();
  cells->ShallowCopy(threshold->GetOutput());
  cells->GetCellData()->RemoveArray(kRankArray);
  cells->GetFieldData()->ShallowCopy(bodies->GetFieldData());
  return cells;
}
} // namespace

//------------------------------------------------------------------------------
vtkMultiProcessController* vtkSoftBodyDistribution::ParallelController()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* vtkSoftBodyDistribution::LocalBodies(
  vtkUnstructuredGrid* piece, vtkMultiProcessController* controller, bool together)
{
  // Decided together: if any rank's piece changed, every rank takes part in redistributing.
  int changed = (!this->Local || piece != this->Piece || piece->GetMTime() != this->PieceMTime ||
                  together != this->Together) ? 1 : 0;
  int anyChanged = 0;
  controller->AllReduce(&changed, &anyChanged, 1, vtkCommunicator::MAX_OP);
  this->LastRedistributed = anyChanged != 0;
  if (anyChanged)
  {
    this->Redistribute(piece, controller, together);
    this->Piece = piece;
    this->PieceMTime = piece->GetMTime();
    this->Together = together;
  }
  return this->Local;
}

//------------------------------------------------------------------------------
void vtkSoftBodyDistribution::Redistribute(
  vtkUnstructuredGrid* piece, vtkMultiProcessController* controller, bool together)
{
  const int rank = controller->GetLocalProcessId();
  const int ranks = controller->GetNumberOfProcesses();

  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  controller->Gather(OwnedCells(piece), pieces, 0);

  int bodies = 0;
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> dealt(static_cast<std::size_t>(ranks));
  if (rank == 0)
  {
    // The whole input: the pieces appended, the points they share merged.
    vtkNew<vtkAppendFilter> append;
    append->MergePointsOn();
    append->SetTolerance(0.0);
    vtkFieldData* fieldData = nullptr;
    for (const vtkSmartPointer<vtkDataObject>& gathered : pieces)
    {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(gathered);
      if (grid && grid->GetNumberOfCells() > 0)
      {
        append->AddInputData(grid);
        fieldData = fieldData ? fieldData : grid->GetFieldData();
      }
    }
    if (append->GetNumberOfInputConnections(0) > 0)
    {
      // Bodies: connected components, each dealt whole, largest first to the least loaded rank
      // (all to rank 0 when they collide with each other).
      // (Not vtkConnectivityFilter: in ParaView its factory makes vtkPConnectivityFilter, which
      // communicates and would wait for the other ranks while only rank 0 runs here.)
      append->Update();
      auto whole = vtkSmartPointer<vtkUnstructuredGrid>::New();
      whole->ShallowCopy(append->GetOutput());
      if (fieldData)
      {
        whole->GetFieldData()->ShallowCopy(fieldData);
      }
      const softbody::Components components = BodiesOf(whole);
      bodies = components.count;
      std::vector<vtkIdType> cellsOfBody(static_cast<std::size_t>(bodies), 0);
      for (std::int32_t body : components.ofCell)
      {
        ++cellsOfBody[static_cast<std::size_t>(body)];
      }
      std::vector<int> order(static_cast<std::size_t>(bodies));
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return cellsOfBody[static_cast<std::size_t>(a)] > cellsOfBody[static_cast<std::size_t>(b)];
      });
      std::vector<vtkIdType> load(static_cast<std::size_t>(ranks), 0);
      std::vector<int> rankOfBody(static_cast<std::size_t>(bodies), 0);
      for (int body : order)
      {
        const auto least = together ? 0 : std::min_element(load.begin(), load.end()) - load.begin();
        rankOfBody[static_cast<std::size_t>(body)] = static_cast<int>(least);
        load[static_cast<std::size_t>(least)] += cellsOfBody[static_cast<std::size_t>(body)];
      }
      vtkNew<vtkIntArray> owner;
      owner->SetName(kRankArray);
      owner->SetNumberOfValues(whole->GetNumberOfCells());
      for (vtkIdType c = 0; c < whole->GetNumberOfCells(); ++c)
      {
        owner->SetValue(c, rankOfBody[static_cast<std::size_t>(components.ofCell[static_cast<std::size_t>(c)])]);
      }
      whole->GetCellData()->AddArray(owner);
      for (int r = 0; r < ranks; ++r)
      {
        dealt[static_cast<std::size_t>(r)] = CellsOfRank(whole, r);
      }
    }
    for (int r = 1; r < ranks; ++r)
    {
      vtkSmartPointer<vtkUnstructuredGrid> grid = dealt[static_cast<std::size_t>(r)];
      if (!grid)
      {
        grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
      }
      controller->Send(grid, r, kBodiesTag);
    }
    this->Local = dealt[0] ? dealt[0] : vtkSmartPointer<vtkUnstructuredGrid>::New();
  }
  else
  {
    this->Local = vtkSmartPointer<vtkUnstructuredGrid>::New();
    controller->Receive(this->Local, 0, kBodiesTag);
  }
  controller->Broadcast(&bodies, 1, 0);
  this->NumberOfBodies = bodies;
}

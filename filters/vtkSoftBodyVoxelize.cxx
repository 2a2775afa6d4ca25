#include "vtkSoftBodyVoxelize.h"

#include "vtkSoftBodySurfaceInput.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImplicitPolyDataDistance.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"
#include "softbody/common/validation.h"
#include "softbody/lattice/lattice.h"
#include "softbody/mesh/tetrahedralize.h" // checkClosedManifold

#include <algorithm>
#include <cmath>
#include <sstream>
#include <functional>
#include <mutex>

vtkStandardNewMacro(vtkSoftBodyVoxelize);

namespace
{
/// Classifies lattice slices with a distance object of the calling thread's own, made on
/// first use from a private copy of the surface (the copy is taken under a lock: the shared
/// surface is only read, but VTK's copy paths may touch its caches).
struct SliceClassifier
{
  vtkPolyData* Surface;
  std::function<void(vtkImplicitPolyDataDistance*, int)> Classify;
  vtkSMPThreadLocal<vtkSmartPointer<vtkPolyData>> Copy;
  vtkSMPThreadLocal<vtkSmartPointer<vtkImplicitPolyDataDistance>> Distance;
  std::mutex CopyLock;

  SliceClassifier(vtkPolyData* surface, std::function<void(vtkImplicitPolyDataDistance*, int)> classify)
    : Surface(surface)
    , Classify(std::move(classify))
  {
  }

  void Initialize()
  {
    vtkSmartPointer<vtkImplicitPolyDataDistance>& distance = this->Distance.Local();
    if (distance)
    {
      return; // this thread's copy from an earlier block
    }
    auto copy = vtkSmartPointer<vtkPolyData>::New();
    {
      std::lock_guard<std::mutex> lock(this->CopyLock);
      auto corners = vtkSmartPointer<vtkPoints>::New();
      corners->DeepCopy(this->Surface->GetPoints());
      auto polys = vtkSmartPointer<vtkCellArray>::New();
      polys->DeepCopy(this->Surface->GetPolys());
      copy->SetPoints(corners);
      copy->SetPolys(polys);
    }
    this->Copy.Local() = copy;
    distance = vtkSmartPointer<vtkImplicitPolyDataDistance>::New();
    distance->SetInput(copy);
  }

  void operator()(vtkIdType begin, vtkIdType end)
  {
    for (vtkIdType k = begin; k < end; ++k)
    {
      this->Classify(this->Distance.Local(), static_cast<int>(k));
    }
  }

  void Reduce() {}
};

constexpr double kMaxNodes = 2.0e8; // ~1.6 GB of flags and maps: refuse beyond, with the reason
}

//------------------------------------------------------------------------------
int vtkSoftBodyVoxelize::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkSoftBodyVoxelize::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro("Missing input or output data object.");
    return 0;
  }
  if (input->GetNumberOfPoints() == 0 || input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    vtkErrorMacro("The input has no polygons: Soft Body Voxelize needs a closed surface.");
    return 0;
  }
  // Refused with the value given (the setters do not clamp).
  try
  {
    softbody::check::positive("Density", this->Density, "kg/m^3");
    softbody::check::nonNegative("Spacing", this->Spacing, "m", "from Resolution");
    softbody::check::atLeast("Resolution", this->Resolution, 1);
    softbody::check::nonNegative("DiagonalStiffness", this->DiagonalStiffness);
    softbody::check::inRange("NumberOfThreads", this->NumberOfThreads, 0, 64);
    if (this->OutputCells != LINKS && this->OutputCells != TETRAHEDRA)
    {
      softbody::check::badChoice("OutputCells", this->OutputCells, "0 (links), 1 (tetrahedra)");
    }
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }

  // The inside test is only meaningful for a closed, consistently oriented surface.
  vtkSmartPointer<vtkPolyData> triangles = vtkSoftBodySurfaceInput::CleanTriangles(input);
  std::vector<softbody::Vec3> points;
  std::vector<std::array<std::int32_t, 3>> faces;
  vtkSoftBodySurfaceInput::ToCore(triangles, points, faces);
  const softbody::SurfaceCheck check = softbody::checkClosedManifold(points, faces);
  if (!check.ok())
  {
    vtkErrorMacro("The surface does not enclose a volume: "
      << check.boundaryEdges << " boundary edges (holes), " << check.nonManifoldEdges
      << " non-manifold edges, " << check.inconsistentEdges << " inconsistently oriented edges, "
      << check.degenerateTriangles << " degenerate triangles, " << check.nonFinitePoints
      << " non-finite points. Close or clean it first (e.g. Fill Holes, Clean).");
    return 0;
  }

  double bounds[6];
  triangles->GetBounds(bounds);
  const double extent[3] = { bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4] };
  const double longest = std::max({ extent[0], extent[1], extent[2] });
  const double h = this->Spacing > 0.0 ? this->Spacing : longest / this->Resolution;
  if (!(h > 0.0) || !std::isfinite(h))
  {
    vtkErrorMacro("The surface is flat or the spacing invalid (h = " << h << ").");
    return 0;
  }
  // Nodes cover the bounding box, centered on it so the lattice sits symmetrically inside.
  softbody::LatticeGrid grid;
  grid.spacing = h;
  double nodes = 1.0;
  for (int a = 0; a < 3; ++a)
  {
    const int n = static_cast<int>(std::floor(extent[a] / h)) + 1;
    grid.nodes[static_cast<std::size_t>(a)] = n;
    grid.origin[a] = bounds[2 * a] + 0.5 * (extent[a] - (n - 1) * h);
    nodes *= n;
  }
  if (nodes > kMaxNodes)
  {
    vtkErrorMacro("Spacing " << h << " m gives " << nodes << " lattice nodes (more than "
                             << kMaxNodes << "): choose a larger spacing.");
    return 0;
  }

  // Signed distance from VTK: negative inside. The distance is 1-Lipschitz, so a node at
  // distance |d| from the surface shares its side with every node closer than |d| along its
  // row: those are skipped without evaluating (the same flags as evaluating every node, at a
  // fraction of the cost: only the rows' ends and the band around the surface are evaluated).
  std::vector<char> inside(grid.nodeCount(), 0);
  auto classifySlice = [&](vtkImplicitPolyDataDistance* distance, int k) {
    for (int j = 0; j < grid.nodes[1]; ++j)
    {
      int i = 0;
      while (i < grid.nodes[0])
      {
        const softbody::Vec3 p = grid.position(i, j, k);
        double x[3] = { p.x(), p.y(), p.z() };
        const double d = distance->EvaluateFunction(x);
        const char side = d < 0.0 ? 1 : 0;
        // Nodes i .. i + reach - 1 lie strictly closer than |d|: same side. At least one.
        const int reach = std::max(1, static_cast<int>(std::ceil(std::abs(d) / h)));
        const int end = std::min(grid.nodes[0], i + reach);
        for (int m = i; m < end; ++m)
        {
          inside[grid.nodeIndex(m, j, k)] = side;
        }
        i = end;
      }
    }
  };
  // One distance object per thread, each on a private copy of the surface's geometry (points
  // and triangles, no attribute arrays). Sharing the cleaned surface makes the flags change
  // from run to run with 2 or more threads (1,604 to 1,613 particles on bunny_10k.obj; always
  // the same with 1 thread): VTK 9.1's
  // vtkImplicitPolyDataDistance::SetInput keeps a triangle-filtered polydata that still shares
  // the caller's vtkPoints and point data, and queries on shared VTK data objects are not
  // thread-safe (const-looking calls refresh internal caches). A shared object flips a node's
  // inside/outside sign now and then, and the distance-based skipping copies a flag to the
  // nodes it skips. Private copies cost one surface per thread and make the flags independent
  // of the thread count. Each slice is written by the thread that classifies it, so no two
  // write one flag; slices go in blocks so progress and abort are handled between blocks, on
  // this thread, as VTK requires.
  SliceClassifier classifier{ triangles, classifySlice };
  // Debian's VTK defaults to the sequential SMP backend: ask for its std::thread one here.
  const vtkSMPTools::Config threads{ this->NumberOfThreads, "STDThread", false };
  const int block = std::max(1, grid.nodes[2] / 20);
  for (int first = 0; first < grid.nodes[2]; first += block)
  {
    this->UpdateProgress(0.9 * first / grid.nodes[2]);
    if (this->CheckAbort())
    {
      return 1;
    }
    const int last = std::min(grid.nodes[2], first + block);
    vtkSMPTools::LocalScope(threads, [&] { vtkSMPTools::For(first, last, 1, classifier); });
  }

  softbody::Lattice lattice;
  try
  {
    lattice = softbody::buildLattice(grid, inside);
  }
  catch (const softbody::InvalidInputError& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  if (lattice.points.empty())
  {
    vtkErrorMacro("No lattice node lies inside the surface: choose a smaller Spacing (now "
      << h << " m) or a larger Resolution.");
    return 0;
  }

  // Tetrahedra keep only the particles of full cells (the others would be in no tet).
  const bool tets = this->OutputCells == TETRAHEDRA;
  std::vector<softbody::Tet> cells;
  std::vector<vtkIdType> newIndex(lattice.points.size(), 0);
  if (tets)
  {
    cells = softbody::latticeTets(lattice);
    if (cells.empty())
    {
      vtkErrorMacro("No lattice cell lies fully inside the surface: choose a smaller Spacing (now "
        << h << " m) or a larger Resolution.");
      return 0;
    }
    std::fill(newIndex.begin(), newIndex.end(), -1);
    for (const softbody::Tet& t : cells)
    {
      for (std::int32_t p : t)
      {
        newIndex[static_cast<std::size_t>(p)] = 0;
      }
    }
  }
  vtkIdType kept = 0;
  for (vtkIdType& id : newIndex)
  {
    id = id < 0 ? -1 : kept++;
  }

  auto outPoints = vtkSmartPointer<vtkPoints>::New();
  outPoints->SetDataTypeToDouble();
  outPoints->SetNumberOfPoints(kept);
  auto mass = vtkSmartPointer<vtkDoubleArray>::New();
  mass->SetName("Mass");
  mass->SetNumberOfValues(kept);
  auto index = vtkSmartPointer<vtkIntArray>::New();
  index->SetName("LatticeIndex");
  index->SetNumberOfComponents(3);
  index->SetNumberOfTuples(kept);
  for (std::size_t p = 0; p < lattice.points.size(); ++p)
  {
    const vtkIdType id = newIndex[p];
    if (id < 0)
    {
      continue;
    }
    outPoints->SetPoint(id, lattice.points[p].data());
    mass->SetValue(id, this->Density * h * h * h);
    for (int a = 0; a < 3; ++a)
    {
      index->SetTypedComponent(id, a, lattice.nodeOfParticle[p][static_cast<std::size_t>(a)]);
    }
  }
  output->SetPoints(outPoints);
  output->GetPointData()->AddArray(index);

  if (tets)
  {
    // Masses come from the Soft Body filter's Density over the tet volumes (a voxel mass
    // would overweight the boundary particles, which carry only part of a voxel).
    output->AllocateExact(static_cast<vtkIdType>(cells.size()), 4 * static_cast<vtkIdType>(cells.size()));
    for (const softbody::Tet& t : cells)
    {
      const vtkIdType ids[4] = { newIndex[std::size_t(t[0])], newIndex[std::size_t(t[1])],
        newIndex[std::size_t(t[2])], newIndex[std::size_t(t[3])] };
      output->InsertNextCell(VTK_TETRA, 4, ids);
    }
  }
  else
  {
    output->GetPointData()->AddArray(mass);
    output->AllocateExact(static_cast<vtkIdType>(lattice.links.size()), 2 * static_cast<vtkIdType>(lattice.links.size()));
    auto scale = vtkSmartPointer<vtkDoubleArray>::New();
    scale->SetName("LinkStiffnessScale");
    auto kind = vtkSmartPointer<vtkUnsignedCharArray>::New();
    kind->SetName("LinkKind");
    for (std::size_t l = 0; l < lattice.links.size(); ++l)
    {
      if (lattice.linkKinds[l] != softbody::LatticeLinkKind::Axis && this->DiagonalStiffness == 0.0)
      {
        continue;
      }
      const vtkIdType ends[2] = { lattice.links[l][0], lattice.links[l][1] };
      output->InsertNextCell(VTK_LINE, 2, ends);
      scale->InsertNextValue(lattice.linkKinds[l] == softbody::LatticeLinkKind::Axis ? 1.0 : this->DiagonalStiffness);
      kind->InsertNextValue(static_cast<unsigned char>(lattice.linkKinds[l]));
    }
    output->GetCellData()->AddArray(scale);
    output->GetCellData()->AddArray(kind);
  }

  auto origin = vtkSmartPointer<vtkDoubleArray>::New();
  origin->SetName("LatticeOrigin");
  origin->SetNumberOfComponents(3);
  origin->InsertNextTuple(grid.origin.data());
  auto spacing = vtkSmartPointer<vtkDoubleArray>::New();
  spacing->SetName("LatticeSpacing");
  spacing->InsertNextValue(h);
  auto dimensions = vtkSmartPointer<vtkIntArray>::New();
  dimensions->SetName("LatticeDimensions");
  dimensions->SetNumberOfComponents(3);
  dimensions->InsertNextTypedTuple(grid.nodes.data());
  auto radius = vtkSmartPointer<vtkDoubleArray>::New();
  radius->SetName("ParticleRadius");
  radius->InsertNextValue(0.5 * h);
  for (vtkAbstractArray* array : { static_cast<vtkAbstractArray*>(origin), static_cast<vtkAbstractArray*>(spacing),
         static_cast<vtkAbstractArray*>(dimensions), static_cast<vtkAbstractArray*>(radius) })
  {
    output->GetFieldData()->AddArray(array);
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkSoftBodyVoxelize::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Spacing: " << this->Spacing << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "DiagonalStiffness: " << this->DiagonalStiffness << "\n";
  os << indent << "Density: " << this->Density << "\n";
  os << indent << "OutputCells: " << this->OutputCells << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

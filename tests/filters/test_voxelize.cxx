// filter.voxelize: Soft Body Voxelize and surface skinning through the pipeline.
// - A voxelized sphere has the particle count its volume predicts (within 2%), and every
//   particle is linked to exactly the lattice neighbors it has (26 inside the body).
// - Open surfaces are refused.
// - The Surface output reproduces the given surface exactly on the undeformed body, follows a
//   rigid translation (free fall) exactly, keeps cells and arrays, and gets unit normals; the
//   same for a tet body (TetrahedralizeSurface).
#include "filter_test_support.h"

#include "vtkCellData.h"
#include "vtkClipPolyData.h"
#include "vtkMassProperties.h"
#include "vtkPlane.h"
#include "vtkPolyData.h"
#include "vtkSoftBodyVoxelize.h"
#include "vtkSphereSource.h"
#include "vtkTetrahedralizeSurface.h"

#include <map>

namespace
{
double SurfaceArea(vtkPolyData* surface)
{
  vtkNew<vtkMassProperties> mass;
  mass->SetInputData(surface);
  mass->Update();
  return mass->GetSurfaceArea();
}

/// The Surface output at time t of a free-falling (no floor) body: every point must be the
/// input surface's point shifted by the body's (uniform) displacement.
void CheckSkinnedFreeFall(vtkUnstructuredGrid* body, vtkPolyData* surface, const char* what)
{
  sbtest::CapturedFilter f(body);
  vtkNew<vtkPolyData> surfaceCopy;
  surfaceCopy->DeepCopy(surface);
  f.Filter->SetInputData(1, surfaceCopy);
  f.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
  f.Filter->SetFloor(0);
  f.Filter->SetEndTime(0.5);
  f.Filter->SetFrameInterval(0.25);
  SB_CHECK(f.Update(0.0), f.Messages->AllErrors());
  vtkPolyData* skinned = vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Surface)));
  SB_CHECK(skinned && skinned->GetNumberOfPoints() == surface->GetNumberOfPoints() &&
      skinned->GetNumberOfCells() == surface->GetNumberOfCells(),
    what << ": the Surface output has the surface's points and cells");
  if (!skinned || skinned->GetNumberOfPoints() != surface->GetNumberOfPoints())
  {
    return;
  }
  double worst = 0.0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(skinned->GetPoint(i), surface->GetPoint(i))));
  }
  SB_CHECK(worst < 1e-12, what << ": undeformed body reproduces the surface (max error " << worst << " m)");
  SB_CHECK(skinned->GetPointData()->GetArray("Marker") != nullptr, what << ": surface arrays pass through");

  SB_CHECK(f.Update(0.5), f.Messages->AllErrors());
  skinned = vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Surface)));
  const double* drop = f.Mesh()->GetPointData()->GetArray("Displacement")->GetTuple3(0);
  const double shift[3] = { drop[0], drop[1], drop[2] };
  SB_CHECK(shift[2] < -1.0, what << ": the body fell (" << shift[2] << " m)");
  worst = 0.0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    const double* p = surface->GetPoint(i);
    const double expected[3] = { p[0] + shift[0], p[1] + shift[1], p[2] + shift[2] };
    worst = std::max(worst, std::sqrt(vtkMath::Distance2BetweenPoints(skinned->GetPoint(i), expected)));
  }
  SB_CHECK(worst < 1e-9, what << ": the surface follows the translation (max error " << worst << " m)");
  SB_CHECK(std::abs(SurfaceArea(skinned) / SurfaceArea(surface) - 1.0) < 1e-9, what << ": area kept");
  vtkDataArray* normals = skinned->GetPointData()->GetNormals();
  SB_CHECK(normals && std::abs(vtkMath::Norm(normals->GetTuple3(0)) - 1.0) < 1e-6, what << ": unit normals");
  SB_CHECK(f.Messages->Errors.empty(), f.Messages->AllErrors());
}
} // namespace

int main()
{
  const double radius = 0.5, spacing = 0.05;
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(64);
  sphere->SetPhiResolution(64);
  sphere->Update();
  vtkNew<vtkPolyData> surface;
  surface->DeepCopy(sphere->GetOutput());
  // A point array, to see that the skinned surface keeps the user's arrays.
  vtkNew<vtkDoubleArray> marker;
  marker->SetName("Marker");
  marker->SetNumberOfValues(surface->GetNumberOfPoints());
  marker->FillValue(7.0);
  surface->GetPointData()->AddArray(marker);

  vtkNew<vtkSoftBodyVoxelize> voxelize;
  voxelize->SetInputData(surface);
  voxelize->SetSpacing(spacing);
  voxelize->Update();
  vtkUnstructuredGrid* lattice = voxelize->GetOutput();
  const double volume = [&] {
    vtkNew<vtkMassProperties> mass;
    mass->SetInputData(surface);
    mass->Update();
    return mass->GetVolume();
  }();
  const double expected = volume / (spacing * spacing * spacing);
  const double count = static_cast<double>(lattice->GetNumberOfPoints());
  SB_CHECK(std::abs(count / expected - 1.0) < 0.02,
    "particle count " << count << " vs volume / h^3 = " << expected);

  // Degree of each particle = the number of lattice neighbors it has.
  vtkDataArray* index = lattice->GetPointData()->GetArray("LatticeIndex");
  std::map<std::array<int, 3>, vtkIdType> byNode;
  for (vtkIdType p = 0; p < lattice->GetNumberOfPoints(); ++p)
  {
    byNode[{ int(index->GetComponent(p, 0)), int(index->GetComponent(p, 1)), int(index->GetComponent(p, 2)) }] = p;
  }
  std::vector<int> degree(static_cast<std::size_t>(lattice->GetNumberOfPoints()), 0);
  for (vtkIdType c = 0; c < lattice->GetNumberOfCells(); ++c)
  {
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    lattice->GetCellPoints(c, npts, ids);
    ++degree[static_cast<std::size_t>(ids[0])];
    ++degree[static_cast<std::size_t>(ids[1])];
  }
  int interior = 0, wrong = 0;
  for (const auto& [node, p] : byNode)
  {
    int neighbors = 0;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          neighbors += (di || dj || dk) && byNode.count({ node[0] + di, node[1] + dj, node[2] + dk });
    wrong += neighbors != degree[static_cast<std::size_t>(p)];
    interior += neighbors == 26;
  }
  SB_CHECK(wrong == 0, wrong << " particles have a link count other than their neighbor count");
  SB_CHECK(interior > count / 2, "most particles are interior with 26 links (" << interior << ")");
  SB_CHECK(std::abs(lattice->GetPointData()->GetArray("Mass")->GetTuple1(0) - 1100.0 * spacing * spacing * spacing) < 1e-12,
    "each particle carries its voxel's mass at the default Density 1100 kg/m^3 (the Soft Body filter's)");

  // An open surface (the sphere without its top cap) encloses nothing.
  vtkNew<vtkPlane> cut;
  cut->SetOrigin(0, 0, 0.4);
  cut->SetNormal(0, 0, -1);
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(surface);
  clip->SetClipFunction(cut);
  vtkNew<vtkSoftBodyVoxelize> open;
  open->SetInputConnection(clip->GetOutputPort());
  sbtest::MessageCatcher* catcher = sbtest::MessageCatcher::New();
  open->AddObserver(vtkCommand::ErrorEvent, catcher);
  open->Update();
  SB_CHECK(catcher->AllErrors().find("boundary edges") != std::string::npos,
    "an open surface is refused: " << catcher->AllErrors());
  catcher->Delete();

  // Tetrahedra output: a conforming tet mesh Mass-Spring simulates (and skinning still binds
  // to the lattice).
  {
    vtkNew<vtkSoftBodyVoxelize> toTets;
    toTets->SetInputData(surface);
    toTets->SetSpacing(0.1);
    toTets->SetOutputCells(vtkSoftBodyVoxelize::TETRAHEDRA);
    toTets->Update();
    vtkNew<vtkUnstructuredGrid> solid;
    solid->DeepCopy(toTets->GetOutput());
    SB_CHECK(solid->GetNumberOfCells() > 0 && solid->GetNumberOfCells() % 6 == 0, "6 tets per full voxel");
    double tetVolume = 0.0;
    for (vtkIdType c = 0; c < solid->GetNumberOfCells(); ++c)
    {
      SB_CHECK(solid->GetCellType(c) == VTK_TETRA, "cell " << c << " is a tet");
      const vtkIdType* ids = nullptr;
      vtkIdType npts = 0;
      solid->GetCellPoints(c, npts, ids);
      double p[4][3];
      for (int k = 0; k < 4; ++k)
      {
        solid->GetPoint(ids[k], p[k]);
      }
      tetVolume += sbtest::TetVolume(p[0], p[1], p[2], p[3]);
    }
    SB_CHECK(tetVolume > 0.5 * volume && tetVolume < volume, "voxel tets fill the inside ("
      << tetVolume << " of " << volume << " m^3)");
    sbtest::CapturedFilter f(solid);
    vtkNew<vtkPolyData> skin;
    skin->DeepCopy(surface);
    f.Filter->SetInputData(1, skin);
    f.Filter->SetEndTime(0.2);
    f.Filter->SetFrameInterval(0.1);
    f.Filter->SetFloor(0);
    SB_CHECK(f.Update(0.2), "Mass-Spring on the voxel tets: " << f.Messages->AllErrors());
    vtkPolyData* skinned = vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Surface)));
    SB_CHECK(skinned && skinned->GetNumberOfPoints() == surface->GetNumberOfPoints(), "skinned surface");
    const double drop = f.Mesh()->GetPointData()->GetArray("Displacement")->GetTuple3(0)[2];
    SB_CHECK(std::abs(drop + 0.5 * 9.81 * 0.04) < 0.02, "it falls about g t^2 / 2 (" << drop << " m)");
  }

  // Skinning onto the lattice and onto a tet mesh of the same sphere.
  vtkNew<vtkUnstructuredGrid> latticeCopy;
  latticeCopy->DeepCopy(lattice);
  CheckSkinnedFreeFall(latticeCopy, surface, "lattice");
  vtkNew<vtkTetrahedralizeSurface> tetrahedralize;
  tetrahedralize->SetInputData(surface);
  tetrahedralize->Update();
  vtkNew<vtkUnstructuredGrid> tets;
  tets->DeepCopy(tetrahedralize->GetOutput());
  CheckSkinnedFreeFall(tets, surface, "tets");
  return sbtest::Result("filter.voxelize");
}

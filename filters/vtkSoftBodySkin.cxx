#include "vtkSoftBodySkin.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGenericCell.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkStaticCellLocator.h"
#include "vtkUnstructuredGrid.h"

#include "softbody/common/errors.h"
#include "softbody/lattice/skin_correction.h"

#include <algorithm>
#include <cmath>
#include <sstream>

//------------------------------------------------------------------------------
void vtkSoftBodySkin::Clear()
{
  this->Skin = softbody::Skin();
  this->Body = this->Surface = nullptr;
  this->Warning.clear();
}

//------------------------------------------------------------------------------
std::string vtkSoftBodySkin::FarSurfaceWarning(
  vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices)
{
  // Distance of the farthest vertex from the body's bounding box: 0 for a surface around or
  // inside the body, about a lattice spacing for a voxelized body's own surface, meters for a
  // surface placed elsewhere or in other units (mm against m).
  double b[6];
  body->GetBounds(b);
  const softbody::Vec3 low(b[0], b[2], b[4]), high(b[1], b[3], b[5]);
  const double size = (high - low).norm();
  double farthest = 0.0;
  for (const softbody::Vec3& v : vertices)
  {
    const softbody::Vec3 outside = (low - v).cwiseMax(v - high).cwiseMax(0.0);
    farthest = std::max(farthest, outside.norm());
  }
  if (!(farthest > kFarFraction * size))
  {
    return {};
  }
  std::ostringstream msg;
  msg.precision(3);
  msg << "The Surface input lies up to " << farthest
      << " m outside the body's bounding box, whose diagonal (the body's size) is " << size
      << " m: it was bound to the nearest cells anyway and moves with them. If it is meant to "
         "be this body's surface, place it on the body (same position and units).";
  return msg.str();
}

//------------------------------------------------------------------------------
std::string vtkSoftBodySkin::Bind(vtkUnstructuredGrid* body, vtkPolyData* surface)
{
  if (this->Body == body && this->Surface == surface && this->BodyTime == body->GetMTime() &&
    this->SurfaceTime == surface->GetMTime() && this->Skin.vertexCount() > 0)
  {
    return {};
  }
  this->Clear();
  if (surface->GetNumberOfPoints() == 0)
  {
    return "the Surface input has no points.";
  }
  std::vector<softbody::Vec3> vertices(static_cast<std::size_t>(surface->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    surface->GetPoint(i, vertices[static_cast<std::size_t>(i)].data());
  }
  this->Warning = FarSurfaceWarning(body, vertices);
  std::string error;
  try
  {
    error = body->GetPointData()->GetArray("LatticeIndex") ? this->BindToLattice(body, vertices)
                                                          : this->BindToTets(body, vertices);
  }
  catch (const softbody::InvalidInputError& e)
  {
    error = e.what();
  }
  if (error.empty())
  {
    if (!this->Warning.empty())
    {
      // Once per binding: Bind returns early while body and surface are unchanged.
      vtkGenericWarningMacro(<< this->Warning);
    }
    this->Body = body;
    this->Surface = surface;
    this->BodyTime = body->GetMTime();
    this->SurfaceTime = surface->GetMTime();
  }
  else
  {
    this->Skin = softbody::Skin();
  }
  return error;
}

//------------------------------------------------------------------------------
std::string vtkSoftBodySkin::BindToLattice(vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices)
{
  vtkDataArray* index = body->GetPointData()->GetArray("LatticeIndex");
  vtkFieldData* field = body->GetFieldData();
  vtkDataArray* origin = field->GetArray("LatticeOrigin");
  vtkDataArray* spacing = field->GetArray("LatticeSpacing");
  vtkDataArray* dimensions = field->GetArray("LatticeDimensions");
  if (index->GetNumberOfComponents() != 3 || !origin || origin->GetNumberOfComponents() != 3 ||
    !spacing || !dimensions || dimensions->GetNumberOfComponents() != 3)
  {
    return "the body has a LatticeIndex array but not the lattice field data of Soft Body "
           "Voxelize (LatticeOrigin, LatticeSpacing, LatticeDimensions).";
  }
  softbody::Lattice lattice;
  softbody::LatticeGrid& grid = lattice.grid;
  origin->GetTuple(0, grid.origin.data());
  grid.spacing = spacing->GetTuple1(0);
  for (int a = 0; a < 3; ++a)
  {
    grid.nodes[static_cast<std::size_t>(a)] = static_cast<int>(dimensions->GetComponent(0, a));
  }
  if (!(grid.spacing > 0.0) || grid.nodes[0] < 1 || grid.nodes[1] < 1 || grid.nodes[2] < 1)
  {
    return "the body's lattice field data is invalid.";
  }
  lattice.particleOfNode.assign(grid.nodeCount(), -1);
  lattice.points.resize(static_cast<std::size_t>(body->GetNumberOfPoints()));
  for (vtkIdType p = 0; p < body->GetNumberOfPoints(); ++p)
  {
    int ijk[3];
    for (int a = 0; a < 3; ++a)
    {
      ijk[a] = static_cast<int>(index->GetComponent(p, a));
      if (ijk[a] < 0 || ijk[a] >= grid.nodes[static_cast<std::size_t>(a)])
      {
        return "LatticeIndex of point " + std::to_string(p) + " lies outside the lattice.";
      }
    }
    softbody::Vec3& x = lattice.points[static_cast<std::size_t>(p)];
    body->GetPoint(p, x.data());
    // The trilinear binding assumes the particles sit on the lattice nodes.
    if ((x - grid.position(ijk[0], ijk[1], ijk[2])).norm() > 1e-6 * grid.spacing)
    {
      return "the lattice's points no longer sit on its nodes (was it transformed after Soft "
             "Body Voxelize?): transform the surface before voxelizing instead.";
    }
    lattice.particleOfNode[grid.nodeIndex(ijk[0], ijk[1], ijk[2])] = static_cast<std::int32_t>(p);
  }
  this->Skin = softbody::bindToLattice(lattice, vertices);
  return {};
}

//------------------------------------------------------------------------------
std::string vtkSoftBodySkin::BindToTets(vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices)
{
  // A grid of the body's tets only, for the locator (other cells cannot carry a surface).
  vtkNew<vtkUnstructuredGrid> tetGrid;
  tetGrid->SetPoints(body->GetPoints());
  std::vector<softbody::Tet> tets;
  for (vtkIdType c = 0; c < body->GetNumberOfCells(); ++c)
  {
    if (body->GetCellType(c) != VTK_TETRA)
    {
      continue;
    }
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    body->GetCellPoints(c, npts, ids);
    tetGrid->InsertNextCell(VTK_TETRA, npts, ids);
    tets.push_back({ static_cast<std::int32_t>(ids[0]), static_cast<std::int32_t>(ids[1]),
      static_cast<std::int32_t>(ids[2]), static_cast<std::int32_t>(ids[3]) });
  }
  if (tets.empty())
  {
    return "skinning a Surface needs a body of tetrahedra or a Soft Body Voxelize lattice; this "
           "body has neither.";
  }
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(tetGrid);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;
  std::vector<std::int32_t> tetOfVertex(vertices.size(), -1);
  for (std::size_t v = 0; v < vertices.size(); ++v)
  {
    double x[3] = { vertices[v].x(), vertices[v].y(), vertices[v].z() };
    double pcoords[3], weights[4];
    vtkIdType found = locator->FindCell(x, 0.0, cell, pcoords, weights);
    if (found < 0)
    {
      double closest[3], dist2 = 0.0;
      int subId = 0;
      locator->FindClosestPoint(x, closest, cell, found, subId, dist2);
    }
    if (found < 0)
    {
      return "a surface vertex could not be placed in or near any tetrahedron.";
    }
    tetOfVertex[v] = static_cast<std::int32_t>(found);
  }
  std::vector<softbody::Vec3> points(static_cast<std::size_t>(body->GetNumberOfPoints()));
  for (vtkIdType p = 0; p < body->GetNumberOfPoints(); ++p)
  {
    body->GetPoint(p, points[static_cast<std::size_t>(p)].data());
  }
  this->Skin = softbody::bindToTets(points, tets, vertices, tetOfVertex);
  return {};
}

//------------------------------------------------------------------------------
void vtkSoftBodySkin::Fill(vtkPolyData* surface, const std::vector<softbody::Vec3>& particles,
  vtkPolyData* output, const softbody::FloorPlane* floor,
  const std::vector<softbody::ObstacleSurface>& obstacles) const
{
  std::vector<softbody::Vec3> moved;
  softbody::applySkin(this->Skin, particles, moved);
  // The reach is taken before any correction: how far the skin itself puts a vertex from the
  // particles that the contacts keep outside.
  const std::vector<double> reach =
    obstacles.empty() ? std::vector<double>() : softbody::skinReach(this->Skin, particles, moved);
  const softbody::SkinCorrection onFloor = floor ? softbody::keepAboveFloor(*floor, moved) : softbody::SkinCorrection();
  const softbody::SkinCorrection outOfObstacles =
    obstacles.empty() ? softbody::SkinCorrection() : softbody::keepOutsideObstacles(obstacles, reach, moved);
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(moved.size()));
  for (std::size_t v = 0; v < moved.size(); ++v)
  {
    points->SetPoint(static_cast<vtkIdType>(v), moved[v].data());
  }
  output->CopyStructure(surface);
  output->SetPoints(points);
  output->GetPointData()->PassData(surface->GetPointData());
  output->GetCellData()->PassData(surface->GetCellData());
  output->GetFieldData()->PassData(surface->GetFieldData());
  auto addField = [&](const char* name, double value) {
    vtkNew<vtkDoubleArray> array;
    array->SetName(name);
    array->InsertNextValue(value);
    output->GetFieldData()->AddArray(array);
  };
  addField("SkinnedMovedOntoFloor", static_cast<double>(onFloor.moved));
  addField("SkinnedDeepestBelowFloor", onFloor.deepest);
  addField("SkinnedMovedOutOfObstacles", static_cast<double>(outOfObstacles.moved));
  addField("SkinnedDeepestInObstacles", outOfObstacles.deepest);

  // Normals of the moved surface, computed on a copy so the output keeps every cell and point
  // as given (splitting off: one normal per input point).
  vtkNew<vtkPolyData> shape;
  shape->SetPoints(points);
  shape->SetPolys(surface->GetPolys());
  shape->SetStrips(surface->GetStrips());
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(shape);
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->AutoOrientNormalsOff();
  normals->ComputePointNormalsOn();
  normals->ComputeCellNormalsOff();
  normals->Update();
  vtkDataArray* computed = normals->GetOutput()->GetPointData()->GetNormals();
  if (computed && computed->GetNumberOfTuples() == output->GetNumberOfPoints())
  {
    output->GetPointData()->SetNormals(computed);
  }
}

#include "vtkSoftBodyInputConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>

//------------------------------------------------------------------------------
bool vtkSoftBodyInputConversion::IsNoArray(const std::string& name)
{
  return name.empty() || name == "None";
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::CheckSize(vtkUnstructuredGrid* input)
{
  if (!input || input->GetNumberOfPoints() == 0 || input->GetNumberOfCells() == 0 ||
    !input->GetCells())
  {
    return "empty input: the soft body needs a mesh with points and cells.";
  }
  // Core indexes points with 32-bit integers (half the memory of vtkIdType in its hot arrays).
  if (input->GetNumberOfPoints() > std::numeric_limits<std::int32_t>::max())
  {
    return "the input has too many points for the simulation (more than 2^31 - 1).";
  }
  return {};
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::Convert(
  vtkUnstructuredGrid* input, const std::string& pinnedArrayName, softbody::Body& body)
{
  std::string error = CheckSize(input);
  if (!error.empty())
  {
    return error;
  }
  error = ConvertTets(input, body.mesh);
  if (error.empty())
  {
    error = ConvertPoints(input, body.mesh);
  }
  if (error.empty())
  {
    error = ConvertPinned(input, pinnedArrayName, body.pinned);
  }
  return error;
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::ConvertTets(
  vtkUnstructuredGrid* input, softbody::TetMesh& mesh)
{
  const vtkIdType numCells = input->GetNumberOfCells();

  // Count the cells that are not tets by type, so the message says what was found.
  std::map<int, vtkIdType> otherTypes;
  vtkIdType otherCount = 0;
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const int type = input->GetCellType(c);
    if (type != VTK_TETRA)
    {
      ++otherTypes[type];
      ++otherCount;
    }
  }
  if (otherCount > 0)
  {
    std::ostringstream msg;
    msg << otherCount << " of the " << numCells
        << " input cells are not tetrahedra (";
    const char* separator = "";
    for (const auto& typeCount : otherTypes)
    {
      const char* name = vtkCellTypes::GetClassNameFromTypeId(typeCount.first);
      msg << separator << typeCount.second << " " << (name ? name : "unknown cell type");
      separator = ", ";
    }
    // Links and vertices only: a particle body (Soft Body Voxelize, Soft Body Cloth), which the
    // position-based methods simulate; remeshing would be the wrong advice.
    const bool particleBody = std::all_of(otherTypes.begin(), otherTypes.end(), [](const auto& t) {
      return t.first == VTK_LINE || t.first == VTK_POLY_LINE || t.first == VTK_VERTEX ||
        t.first == VTK_POLY_VERTEX;
    });
    if (particleBody)
    {
      msg << "): a body of linked particles, as Soft Body Voxelize and Soft Body Cloth make. "
             "Mass-Spring simulates tetrahedra only: choose Method XPBD (or PBD), which "
             "simulates linked particles, or give Soft Body Voxelize OutputCells = Tetrahedra.";
      return msg.str();
    }
    msg << "). The soft body simulates tetrahedral meshes only: mesh the body's surface with "
           "Soft Body's Tetrahedralize Surface (TetGen) filter (Extract Surface first), or split "
           "the cells with ParaView's Tetrahedralize filter.";
    return msg.str();
  }

  mesh.tets.resize(static_cast<std::size_t>(numCells));
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    input->GetCellPoints(c, npts, pts);
    if (npts != 4)
    {
      std::ostringstream msg;
      msg << "input cell " << c << " is marked as a tetrahedron but has " << npts << " points.";
      return msg.str();
    }
    softbody::Tet& tet = mesh.tets[static_cast<std::size_t>(c)];
    for (int k = 0; k < 4; ++k)
    {
      // Ids out of range are left for prepareTetMesh to report ("bad index"); only clamp what
      // would not fit in 32 bits to -1 so it is still reported as out of range.
      const vtkIdType id = pts[k];
      tet[static_cast<std::size_t>(k)] =
        (id < 0 || id > std::numeric_limits<std::int32_t>::max()) ? -1
                                                                   : static_cast<std::int32_t>(id);
    }
  }
  return {};
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::ConvertPoints(
  vtkUnstructuredGrid* input, softbody::TetMesh& mesh)
{
  vtkPoints* points = input->GetPoints();
  const vtkIdType numPoints = points->GetNumberOfPoints();
  mesh.points.resize(static_cast<std::size_t>(numPoints));
  // GetPoint converts float (or any other type) to double once; non-finite values pass through
  // and are reported by prepareTetMesh.
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    double x[3];
    points->GetPoint(p, x);
    mesh.points[static_cast<std::size_t>(p)] = softbody::Vec3(x[0], x[1], x[2]);
  }
  return {};
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::ConvertPinned(
  vtkUnstructuredGrid* input, const std::string& pinnedArrayName, std::vector<char>& pinned)
{
  pinned.clear();
  if (IsNoArray(pinnedArrayName))
  {
    return {};
  }
  vtkAbstractArray* abstractArray = input->GetPointData()->GetAbstractArray(pinnedArrayName.c_str());
  if (!abstractArray)
  {
    return "the pinned-points array '" + pinnedArrayName +
      "' is not a point-data array of the input. Choose an existing point array or None.";
  }
  vtkDataArray* array = vtkDataArray::SafeDownCast(abstractArray);
  if (!array)
  {
    return "the pinned-points array '" + pinnedArrayName +
      "' is not numeric. Choose a numeric point array (nonzero = pinned) or None.";
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  const int numComponents = array->GetNumberOfComponents();
  pinned.assign(static_cast<std::size_t>(numPoints), 0);
  for (vtkIdType p = 0; p < numPoints; ++p)
  {
    for (int c = 0; c < numComponents; ++c)
    {
      if (array->GetComponent(p, c) != 0.0)
      {
        pinned[static_cast<std::size_t>(p)] = 1;
        break;
      }
    }
  }
  return {};
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::ConvertCellMaterial(vtkUnstructuredGrid* input,
  const std::string& youngsModulusArray, const std::string& poissonRatioArray,
  const std::string& densityArray, softbody::CellMaterial& cells)
{
  const auto read = [&](const char* property, const std::string& name,
                      std::vector<double>& values) -> std::string {
    values.clear();
    if (IsNoArray(name))
    {
      return {};
    }
    vtkDataArray* array = vtkDataArray::SafeDownCast(input->GetCellData()->GetAbstractArray(name.c_str()));
    if (!array)
    {
      return std::string(property) + " '" + name + "' is not a numeric cell-data array of the "
        "input. Choose a numeric cell array (one value per cell) or None.";
    }
    if (array->GetNumberOfComponents() != 1)
    {
      return std::string(property) + " '" + name + "' has " +
        std::to_string(array->GetNumberOfComponents()) + " components; it needs one value per cell.";
    }
    values.resize(static_cast<std::size_t>(array->GetNumberOfTuples()));
    for (vtkIdType c = 0; c < array->GetNumberOfTuples(); ++c)
    {
      values[static_cast<std::size_t>(c)] = array->GetComponent(c, 0);
    }
    return {};
  };
  std::string error = read("YoungsModulusArray", youngsModulusArray, cells.youngsModulus);
  if (error.empty())
  {
    error = read("PoissonRatioArray", poissonRatioArray, cells.poissonRatio);
  }
  if (error.empty())
  {
    error = read("DensityArray", densityArray, cells.density);
  }
  return error;
}

//------------------------------------------------------------------------------
namespace
{
std::int32_t ToIndex(vtkIdType id)
{
  // Out-of-range ids become -1, which core reports as a bad index.
  return (id < 0 || id > std::numeric_limits<std::int32_t>::max()) ? -1
                                                                    : static_cast<std::int32_t>(id);
}

/// Copies a one-component numeric array into `values`; an empty string on success.
std::string ReadScalars(vtkAbstractArray* abstractArray, const char* what, vtkIdType count,
  std::vector<double>& values)
{
  vtkDataArray* array = vtkDataArray::SafeDownCast(abstractArray);
  if (!array || array->GetNumberOfComponents() != 1 || array->GetNumberOfTuples() != count)
  {
    return std::string("the ") + what + " array must be numeric with one value per item.";
  }
  values.resize(static_cast<std::size_t>(count));
  for (vtkIdType i = 0; i < count; ++i)
  {
    values[static_cast<std::size_t>(i)] = array->GetTuple1(i);
  }
  return {};
}
} // namespace

//------------------------------------------------------------------------------
std::string vtkSoftBodyInputConversion::ConvertParticles(vtkUnstructuredGrid* input,
  const std::string& pinnedArrayName, softbody::Body& body, std::vector<vtkIdType>& tetCells,
  std::vector<vtkIdType>& linkCells)
{
  std::string error = CheckSize(input);
  if (!error.empty())
  {
    return error;
  }
  std::vector<double> cellScale;
  if (vtkAbstractArray* scale = input->GetCellData()->GetAbstractArray("LinkStiffnessScale"))
  {
    error = ReadScalars(scale, "LinkStiffnessScale cell", input->GetNumberOfCells(), cellScale);
    if (!error.empty())
    {
      return error;
    }
  }

  std::map<int, vtkIdType> solidTypes; // 3D cells other than tets: refused
  tetCells.clear();
  linkCells.clear();
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const int type = input->GetCellType(c);
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    input->GetCellPoints(c, npts, pts);
    if (type == VTK_TETRA && npts == 4)
    {
      body.mesh.tets.push_back({ ToIndex(pts[0]), ToIndex(pts[1]), ToIndex(pts[2]), ToIndex(pts[3]) });
      tetCells.push_back(c);
    }
    else if (type == VTK_LINE || type == VTK_POLY_LINE)
    {
      for (vtkIdType k = 0; k + 1 < npts; ++k)
      {
        body.links.push_back({ ToIndex(pts[k]), ToIndex(pts[k + 1]) });
        body.linkStiffnessScale.push_back(cellScale.empty() ? 1.0 : cellScale[static_cast<std::size_t>(c)]);
        linkCells.push_back(c);
      }
    }
    else if (vtkCellTypes::GetDimension(static_cast<unsigned char>(type)) == 3)
    {
      ++solidTypes[type];
    }
  }
  if (!solidTypes.empty())
  {
    std::ostringstream msg;
    msg << "PBD and XPBD simulate tetrahedra and line cells; the input also has ";
    const char* separator = "";
    for (const auto& typeCount : solidTypes)
    {
      const char* name = vtkCellTypes::GetClassNameFromTypeId(typeCount.first);
      msg << separator << typeCount.second << " " << (name ? name : "unknown 3D cells");
      separator = ", ";
    }
    msg << ". Mesh the body's surface with Soft Body's Tetrahedralize Surface (TetGen) filter "
           "(Extract Surface first), or split the cells with ParaView's Tetrahedralize filter.";
    return msg.str();
  }
  for (const auto& link : body.links)
  {
    if (link[0] < 0 || link[1] < 0 || link[0] >= input->GetNumberOfPoints() ||
      link[1] >= input->GetNumberOfPoints())
    {
      return "a line cell refers to a point the input does not have.";
    }
  }

  softbody::TetMesh points;
  ConvertPoints(input, points);
  body.mesh.points = std::move(points.points);
  if (vtkAbstractArray* mass = input->GetPointData()->GetAbstractArray("Mass"))
  {
    error = ReadScalars(mass, "Mass point", input->GetNumberOfPoints(), body.pointMass);
    if (!error.empty())
    {
      return error;
    }
  }
  return ConvertPinned(input, pinnedArrayName, body.pinned);
}

/**
 * @class   vtkSoftBodyTetMeshOutput
 * @brief   Writes core's TetMesh into a vtkUnstructuredGrid of VTK_TETRA cells.
 *
 * Shared by the meshing filter and the mesh readers so that they all produce the same grid:
 * double-precision points, one VTK_TETRA per core tet in core's order and corner order.
 */
#ifndef vtkSoftBodyTetMeshOutput_h
#define vtkSoftBodyTetMeshOutput_h

#include "softbody/mesh/mesh_io.h"
#include "softbody/mesh/tet_mesh.h"

#include <string>

class vtkAlgorithm;
class vtkUnstructuredGrid;

class vtkSoftBodyTetMeshOutput
{
public:
  /// Replaces the content of `output` with `mesh`.
  static void Fill(const softbody::TetMesh& mesh, vtkUnstructuredGrid* output);

  /// A core file loader: vtkTetGenReader and vtkGmshReader differ only in this.
  using Loader = softbody::TetMesh (*)(const std::string& path, softbody::MeshFileInfo* info);

  /// The whole RequestData of a tet-mesh reader: loads `fileName` with `load`, fills `output`
  /// and adds field data SkippedElements. Errors are reported on `reader` (vtkErrorMacro
  /// style) and return 0; success returns 1.
  static int ReadFile(vtkAlgorithm* reader, const std::string& fileName, Loader load,
    vtkUnstructuredGrid* output);

  /// The file's groups (Gmsh): cell arrays GmshPhysical and GmshEntity (the tags of each tet's
  /// volume element, 0 = none) and one point array per physical group, named after it, 1 on
  /// the nodes of its elements (points, lines, surfaces or volumes).
  static void AddGroups(const softbody::MeshFileInfo& info, vtkUnstructuredGrid* output);
};

#endif

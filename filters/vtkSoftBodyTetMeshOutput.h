/**
 * @class   vtkSoftBodyTetMeshOutput
 * @brief   Writes core's TetMesh into a vtkUnstructuredGrid of VTK_TETRA cells.
 *
 * Shared by the meshing filter and the mesh readers so that they all produce the same grid:
 * double-precision points, one VTK_TETRA per core tet in core's order and corner order.
 */
#ifndef vtkSoftBodyTetMeshOutput_h
#define vtkSoftBodyTetMeshOutput_h

#include "softbody/tet_mesh.h"

class vtkUnstructuredGrid;

class vtkSoftBodyTetMeshOutput
{
public:
  /// Replaces the content of `output` with `mesh`.
  static void Fill(const softbody::TetMesh& mesh, vtkUnstructuredGrid* output);
};

#endif

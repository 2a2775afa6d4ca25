/**
 * @class   vtkSoftBodySurfaceInput
 * @brief   A closed surface as the meshing filters need it: triangles only, coincident points
 *          merged, and core's arrays.
 *
 * Shared by Tetrahedralize Surface and Soft Body Voxelize. OBJ and many STL files store each
 * triangle with its own copies of its corners, which would make every edge a boundary edge;
 * merging exactly coincident points fixes that and leaves a clean surface unchanged.
 */
#ifndef vtkSoftBodySurfaceInput_h
#define vtkSoftBodySurfaceInput_h

#include "softbody/common/geometry.h"

#include "vtkSmartPointer.h"

#include <array>
#include <cstdint>
#include <vector>

class vtkPolyData;

class vtkSoftBodySurfaceInput
{
public:
  /// Triangulated polygons and strips (vertices and lines dropped), coincident points merged.
  static vtkSmartPointer<vtkPolyData> CleanTriangles(vtkPolyData* input);

  /// The triangles' points and corner indices (non-triangles, i.e. collapsed ones, skipped).
  static void ToCore(vtkPolyData* triangles, std::vector<softbody::Vec3>& points,
    std::vector<std::array<std::int32_t, 3>>& faces);
};

#endif

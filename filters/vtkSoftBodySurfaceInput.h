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

#include "SoftBodyFiltersModule.h" // for export macro
#include "softbody/common/geometry.h"

#include "vtkSmartPointer.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

class vtkDataObject;
class vtkPolyData;

class SOFTBODYFILTERS_EXPORT vtkSoftBodySurfaceInput
{
public:
  /// Triangulated polygons and strips (vertices and lines dropped), coincident points merged.
  static vtkSmartPointer<vtkPolyData> CleanTriangles(vtkPolyData* input);

  /// The triangles' points and corner indices (non-triangles, i.e. collapsed ones, skipped).
  static void ToCore(vtkPolyData* triangles, std::vector<softbody::Vec3>& points,
    std::vector<std::array<std::int32_t, 3>>& faces);

  /// Checks what arrives on the Soft Body filter's optional Surface port (port 1): empty when
  /// it is absent (nullptr) or a vtkPolyData, otherwise one message for the user naming the
  /// type given and the remedy. The port should accept any vtkDataObject and call this, so a
  /// wrong type ends in one clear error instead of the executive's repeated type errors.
  static std::string SkinSurfaceError(vtkDataObject* surface);
};

#endif

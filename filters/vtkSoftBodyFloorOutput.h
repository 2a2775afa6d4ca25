/**
 * @class   vtkSoftBodyFloorOutput
 * @brief   The Soft Body filter's Floor output port: the floor plane as a finite square, so the
 *          plane the body lands on can be seen.
 *
 * A plane is infinite and VTK draws polygons, so the floor is shown as a square on the plane,
 * centered under the body's rest bounding box and sized to it (side twice the box diagonal): large
 * enough to catch a body that falls, bounces or slides a little, small enough that the camera
 * ParaView resets onto the scene still frames the body. It is sized once from the input (the
 * body at rest), so it stays put while the body moves.
 */
#ifndef vtkSoftBodyFloorOutput_h
#define vtkSoftBodyFloorOutput_h

#include "SoftBodyFiltersModule.h" // for export macro

class vtkPolyData;

class SOFTBODYFILTERS_EXPORT vtkSoftBodyFloorOutput
{
public:
  /// Fills `output` with one quad on the plane through `origin` with normal `normal` (nonzero,
  /// any length), centered on the projection of the center of `bodyBounds` (xmin, xmax, ymin,
  /// ymax, zmin, zmax) and with point array Normals; leaves it empty when `floorOn` is false.
  static void Fill(bool floorOn, const double origin[3], const double normal[3],
    const double bodyBounds[6], vtkPolyData* output);
};

#endif

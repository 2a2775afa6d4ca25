/**
 * @class   vtkSoftBodySkin
 * @brief   The Soft Body filter's optional render surface: bound once to the body at rest, then
 *          moved with it every frame.
 *
 * A Soft Body Voxelize lattice (recognized by its LatticeIndex point array and Lattice* field
 * data) binds each surface vertex to the 8 particles of its lattice cell with trilinear
 * weights; a tet body binds it to the 4 corners of its enclosing tet (found with VTK's
 * vtkStaticCellLocator; the nearest tet for vertices outside) with barycentric weights. Both
 * are exact for rigid and affine motions (softbody::bindToLattice, softbody::bindToTets).
 */
#ifndef vtkSoftBodySkin_h
#define vtkSoftBodySkin_h

#include "softbody/collision/obstacle.h"
#include "softbody/common/floor_plane.h"
#include "softbody/lattice/skinning.h"

#include "vtkType.h"

#include <string>

class vtkPolyData;
class vtkUnstructuredGrid;

class vtkSoftBodySkin
{
public:
  /// (Re)binds unless already bound to these objects at these modification times. Returns an
  /// empty string on success, otherwise the message for the user.
  std::string Bind(vtkUnstructuredGrid* body, vtkPolyData* surface);
  void Clear();

  /// `output` = `surface` (same cells and arrays) with its points moved onto the body's
  /// current particle positions and its point normals recomputed.
  /// With a floor, vertices that the skin puts below it are moved onto it, then those it puts
  /// inside an obstacle (`obstacles` at the frame's time) onto its surface: render corrections
  /// (softbody::keepAboveFloor, softbody::keepOutsideObstacles). The output's field data says
  /// how many vertices each moved and the longest move: SkinnedMovedOntoFloor,
  /// SkinnedDeepestBelowFloor [m], SkinnedMovedOutOfObstacles, SkinnedDeepestInObstacles [m].
  void Fill(vtkPolyData* surface, const std::vector<softbody::Vec3>& particles, vtkPolyData* output,
    const softbody::FloorPlane* floor = nullptr,
    const std::vector<softbody::ObstacleSurface>& obstacles = {}) const;

  std::size_t GetOutsideCount() const { return this->Skin.outsideCount; }

  /// Set by the last Bind that bound anew: a Surface that lies far from the body (more than
  /// kFarFraction of the body's bounding-box diagonal outside that box, e.g. misplaced or in
  /// other units) is bound to the nearest cells all the same, and this says so, quoting the
  /// distance and the body's size; empty otherwise. Bind also emits it as a VTK warning.
  const std::string& GetWarning() const { return this->Warning; }

  /// See GetWarning.
  static constexpr double kFarFraction = 0.25;

private:
  static std::string FarSurfaceWarning(
    vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices);
  std::string BindToLattice(vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices);
  std::string BindToTets(vtkUnstructuredGrid* body, const std::vector<softbody::Vec3>& vertices);

  softbody::Skin Skin;
  std::string Warning;
  const void* Body = nullptr; // identities only, never dereferenced
  const void* Surface = nullptr;
  vtkMTimeType BodyTime = 0;
  vtkMTimeType SurfaceTime = 0;
};

#endif

/**
 * @file   vtkSoftBodyOutputAssembly.h
 * @brief  The Soft Body filter's outputs (vtkSoftBodyOutputPort) filled from the simulation at
 *         the requested time: the moved Mesh with its arrays and field data, the Particles, the
 *         Convergence table, the skinned Surface and the Floor square.
 */
#ifndef vtkSoftBodyOutputAssembly_h
#define vtkSoftBodyOutputAssembly_h

#include "vtkSoftBodyOutputPort.h"

#include "softbody/collision/obstacle.h"
#include "softbody/scene/scene.h"

#include <string>
#include <vector>

struct vtkSoftBodyBuiltSimulation;
struct vtkSoftBodyParameters;
class vtkInformationVector;
class vtkPolyData;
class vtkSoftBodySkin;
class vtkTable;
class vtkUnstructuredGrid;

namespace vtkSoftBodyOutputAssembly
{
/// The output data objects, one per port.
struct Outputs
{
  vtkUnstructuredGrid* Mesh = nullptr;
  vtkPolyData* Particles = nullptr;
  vtkTable* Convergence = nullptr;
  vtkPolyData* Surface = nullptr;
  vtkPolyData* Floor = nullptr;
  vtkTable* Timings = nullptr;

  /// Whether every port has its data object.
  bool Complete() const;
};

/// The data type each port produces (FillOutputPortInformation).
const char* DataTypeName(vtkSoftBodyOutputPort port);

/// The output data objects of the filter's output information vector.
Outputs Fetch(vtkInformationVector* outputVector);

/// DATA_TIME_STEP `t` on every output, so each is shown as the requested time.
void StampTime(vtkInformationVector* outputVector, double t);

/// The Mesh port: `input`'s cells and arrays with the simulation's points, point arrays
/// Velocity (the active scalars) and Displacement, cell array VolumeRatio, and the field
/// data. `beforeRun` (what was said before the run: a long run to EndTime, a landing too fast
/// for the implicit step) and `surfaceWarning` (the Surface binding) join Warnings when not
/// empty. Returns the inverted-tets warning, empty when there is none.
std::string FillMesh(vtkUnstructuredGrid* input, const vtkSoftBodyBuiltSimulation& built,
  const vtkSoftBodyParameters& p, const std::vector<std::string>& beforeRun,
  const std::string& surfaceWarning, vtkUnstructuredGrid* output);

/// The Particles port: one vertex per Mesh point, sharing the Mesh's points and Velocity, and
/// point array InverseMass.
void FillParticles(
  const vtkSoftBodyBuiltSimulation& built, vtkUnstructuredGrid* mesh, vtkPolyData* output);

/// The Convergence port: PBD/XPBD's or the implicit integrators' residuals; empty otherwise.
void FillConvergence(const vtkSoftBodyBuiltSimulation& built, vtkTable* output);

/// The Surface port: `surface`, bound by `skin`, moved with the body and kept above the
/// scene's floor (where active) and outside `obstacles`.
void FillSurface(const vtkSoftBodySkin& skin, vtkPolyData* surface,
  const vtkSoftBodyBuiltSimulation& built, const softbody::Scene& scene,
  const std::vector<softbody::ObstacleSurface>& obstacles, vtkPolyData* output);

/// The Floor port: the floor plane as a square under `input`'s rest bounds, where the run put
/// it (`scene`, vtkSoftBodyFloorPlacement; FloorOrigin where the floor is not active); empty
/// when Floor is off. With an active floor, the Mesh's field data FloorOrigin says where it is.
void FillFloor(const vtkSoftBodyParameters& p, const softbody::Scene& scene,
  vtkUnstructuredGrid* input, const Outputs& outputs);
}

#endif

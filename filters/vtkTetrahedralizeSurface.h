/**
 * @class   vtkTetrahedralizeSurface
 * @brief   Fills a closed triangle surface with tetrahedra using TetGen.
 *
 * The input is a vtkPolyData whose polygons (and triangle strips) bound a volume: a closed,
 * manifold, consistently oriented surface, such as an OBJ, STL or PLY model. Polygons are
 * triangulated and exactly coincident points merged first (OBJ files repeat the corners of
 * every triangle); vertices and lines are ignored. The output is a
 * vtkUnstructuredGrid of positively oriented VTK_TETRA cells, ready for vtkSoftBodyFilter.
 *
 * The meshing is softbody::tetrahedralizeSurface (core library, TetGen 1.5 by Hang Si). Open,
 * non-manifold, inconsistently oriented or self-intersecting surfaces are reported with
 * vtkErrorMacro and an empty output; TetGen never ends the process.
 *
 * TetGen itself cannot be interrupted: progress is reported before and after it, and an abort
 * request is honored before it starts.
 */
#ifndef vtkTetrahedralizeSurface_h
#define vtkTetrahedralizeSurface_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class SOFTBODYFILTERS_EXPORT vtkTetrahedralizeSurface : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTetrahedralizeSurface* New();
  vtkTypeMacro(vtkTetrahedralizeSurface, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Largest radius-edge ratio of a tet (TetGen switch q) [-], default 2. Smaller gives rounder
   * tets and more of them; TetGen needs about 1.1 or more to finish. 0 turns refinement off.
   */
  vtkSetMacro(MaxRadiusEdgeRatio, double);
  vtkGetMacro(MaxRadiusEdgeRatio, double);
  ///@}

  ///@{
  /**
   * Smallest dihedral angle TetGen tries to keep [deg] (second value of switch q), default 0
   * (TetGen's own default). Values above ~18 degrees may not terminate.
   */
  vtkSetMacro(MinDihedralAngle, double);
  vtkGetMacro(MinDihedralAngle, double);
  ///@}

  ///@{
  /**
   * Largest tet volume (TetGen switch a); 0 (default) = unbounded. In the input's length unit
   * cubed, or, when MaxTetVolumeIsRelative is on, as a fraction of the volume of the input's
   * bounding box (e.g. 1e-4 gives at least ~10^4 tets over the box).
   */
  vtkSetMacro(MaxTetVolume, double);
  vtkGetMacro(MaxTetVolume, double);
  vtkSetMacro(MaxTetVolumeIsRelative, vtkTypeBool);
  vtkGetMacro(MaxTetVolumeIsRelative, vtkTypeBool);
  vtkBooleanMacro(MaxTetVolumeIsRelative, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Keep the surface as given: no Steiner points on the boundary (TetGen switch Y), so the
   * output's boundary triangles are exactly the input's. Off by default (better tets).
   */
  vtkSetMacro(PreserveBoundary, vtkTypeBool);
  vtkGetMacro(PreserveBoundary, vtkTypeBool);
  vtkBooleanMacro(PreserveBoundary, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Most points TetGen may add (TetGen switch S), default 200000 (about 1.2 million tets);
   * 0 = no limit. Strict quality settings can make TetGen refine without end: at the limit it
   * stops with the mesh it has and the filter warns that the bounds may not be met.
   */
  vtkSetMacro(MaxAddedPoints, int);
  vtkGetMacro(MaxAddedPoints, int);
  ///@}

protected:
  vtkTetrahedralizeSurface();
  ~vtkTetrahedralizeSurface() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double MaxRadiusEdgeRatio = 2.0;
  double MinDihedralAngle = 0.0;
  double MaxTetVolume = 0.0;
  vtkTypeBool MaxTetVolumeIsRelative = 0;
  vtkTypeBool PreserveBoundary = 0;
  int MaxAddedPoints = 200000;

private:
  vtkTetrahedralizeSurface(const vtkTetrahedralizeSurface&) = delete;
  void operator=(const vtkTetrahedralizeSurface&) = delete;
};

#endif

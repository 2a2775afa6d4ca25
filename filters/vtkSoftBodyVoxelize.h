/**
 * @class   vtkSoftBodyVoxelize
 * @brief   Closed surface in, a lattice of particles inside it out, linked to their lattice
 *          neighbors: a body for the Soft Body filter's PBD and XPBD methods.
 *
 * Lattice nodes lie on a regular grid of spacing h (Spacing, or the bounding box's longest side
 * divided by Resolution) whose bounding box covers the surface's. A node is a particle when
 * VTK's vtkImplicitPolyDataDistance puts it inside the surface (negative signed distance).
 * Particles within one voxel diagonal (the 26-neighborhood) are linked: axis links, and face
 * and body diagonals at DiagonalStiffness times the link stiffness. Built in time linear in the
 * grid size (no all-pairs neighbor search).
 *
 * Output (OutputCells = LINKS, the default): a vtkUnstructuredGrid of VTK_LINE cells, one per link, so it composes with the Soft
 * Body filter (links) and with every ParaView filter that takes a grid; cell arrays
 * "LinkStiffnessScale" and "LinkKind" (0 axis, 1 face diagonal, 2 body diagonal); point arrays
 * "Mass" (Density h^3) and "LatticeIndex" (i, j, k); field data "LatticeOrigin",
 * "LatticeSpacing", "LatticeDimensions" and "ParticleRadius" (h / 2), which let the Soft Body
 * filter skin a surface onto the lattice with trilinear weights.
 *
 * OutputCells = TETRAHEDRA instead splits every full lattice cell (8 particle corners) into its
 * 6 Kuhn tets (conforming, positively oriented) and keeps only the particles of those cells:
 * a tet mesh every Soft Body method takes, Mass-Spring and the GPU included, with masses from
 * the Soft Body filter's Density. LatticeIndex and the field data stay, so skinning still uses
 * the lattice.
 */
#ifndef vtkSoftBodyVoxelize_h
#define vtkSoftBodyVoxelize_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class SOFTBODYFILTERS_EXPORT vtkSoftBodyVoxelize : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkSoftBodyVoxelize* New();
  vtkTypeMacro(vtkSoftBodyVoxelize, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum OutputCellsType
  {
    LINKS = 0,
    TETRAHEDRA = 1
  };
  vtkSetMacro(OutputCells, int);
  vtkGetMacro(OutputCells, int);

  /// Lattice spacing h [m]; 0 = the bounding box's longest side / Resolution.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  /// Voxels along the longest side when Spacing is 0 (at least 1).
  vtkSetMacro(Resolution, int);
  vtkGetMacro(Resolution, int);
  /// Stiffness of the diagonal links relative to the axis links (0 = no diagonal links).
  vtkSetMacro(DiagonalStiffness, double);
  vtkGetMacro(DiagonalStiffness, double);
  /// Density [kg/m^3]: each particle carries the mass of its voxel. Default 1100, as the Soft
  /// Body filter's Density, so a lattice and a tet mesh of one surface weigh the same.
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  /// Threads classifying the lattice nodes through vtkSMPTools (0 = one per hardware thread, at
  /// most 64). The result does not depend on it (tests compare 1 and 2); C++ only, not a
  /// ParaView property.
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

protected:
  vtkSoftBodyVoxelize() = default;
  ~vtkSoftBodyVoxelize() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double Spacing = 0.0;
  int Resolution = 20;
  double DiagonalStiffness = 1.0;
  double Density = 1100.0;
  int OutputCells = LINKS;
  int NumberOfThreads = 0;

private:
  vtkSoftBodyVoxelize(const vtkSoftBodyVoxelize&) = delete;
  void operator=(const vtkSoftBodyVoxelize&) = delete;
};

#endif

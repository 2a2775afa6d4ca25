/**
 * @class   vtkSoftBodyStressOutput
 * @brief   The strain and stress of a continuum body on the Soft Body Mesh output.
 *
 * Per cell: GreenStrain and CauchyStress (symmetric tensors, VTK's XX YY ZZ XY YZ XZ order),
 * VonMisesStress [Pa] and StrainEnergyDensity [J/m^3] of each tet. Per point, for smooth
 * colouring: VonMisesStress and CauchyStress averaged over the point's tets, weighted by their
 * rest volumes (so a sliver does not dominate a point). An inverted tet has no Cauchy stress
 * (NaN) and is left out of the averages.
 */
#ifndef vtkSoftBodyStressOutput_h
#define vtkSoftBodyStressOutput_h

#include "softbody/common/geometry.h"
#include "softbody/common/tet_stress_field.h"

#include <vector>

class vtkUnstructuredGrid;

struct vtkSoftBodyStressOutput
{
  /// Adds the arrays when `field` has one entry per cell of `output` (all tets); the rest
  /// positions (in the output's point order) weight the point averages.
  static void Add(const softbody::TetStressField& field,
    const std::vector<softbody::Vec3>& restPositions, vtkUnstructuredGrid* output);
};

#endif

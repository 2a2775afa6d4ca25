/**
 * @class   vtkSoftBodyCloth
 * @brief   Source: the PBD thesis's cloth, an N x M sheet of particles with structural and
 *          diagonal links, ready for the Soft Body filter (PBD or XPBD).
 *
 * The sheet spans Origin + s (Point1 - Origin) + t (Point2 - Origin), s, t in [0, 1], as
 * vtkPlaneSource does. Output (vtkUnstructuredGrid):
 * - one VTK_LINE per link: structural links between grid neighbors, then both diagonals of
 *   every grid cell, with cell array "LinkStiffnessScale" (1 for structural links,
 *   DiagonalStiffness for diagonals), which the Soft Body filter multiplies into the link
 *   stiffness (PBD) or divides into the compliance (XPBD);
 * - one VTK_QUAD per grid cell for rendering (they add no constraint; their
 *   LinkStiffnessScale is 0);
 * - point arrays "Mass" [kg] (TotalMass spread equally) and "Pinned" (1 at the pinned corners:
 *   choose it as the Soft Body filter's PinnedPointsArray).
 */
#ifndef vtkSoftBodyCloth_h
#define vtkSoftBodyCloth_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class SOFTBODYFILTERS_EXPORT vtkSoftBodyCloth : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkSoftBodyCloth* New();
  vtkTypeMacro(vtkSoftBodyCloth, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum PinnedCornersType
  {
    NO_CORNERS = 0,
    POINT2_CORNERS = 1, ///< the two corners of the Point2 edge (the top, when Point2 is up)
    ALL_CORNERS = 2
  };

  vtkSetVector3Macro(Origin, double);
  vtkGetVector3Macro(Origin, double);
  vtkSetVector3Macro(Point1, double);
  vtkGetVector3Macro(Point1, double);
  vtkSetVector3Macro(Point2, double);
  vtkGetVector3Macro(Point2, double);
  /// Particles along Point1 and along Point2 (each at least 2).
  vtkSetVector2Macro(Resolution, int);
  vtkGetVector2Macro(Resolution, int);
  /// Mass of the whole sheet [kg] (> 0).
  vtkSetMacro(TotalMass, double);
  vtkGetMacro(TotalMass, double);
  /// Stiffness of the diagonal links relative to the structural ones (0 = no diagonals).
  vtkSetMacro(DiagonalStiffness, double);
  vtkGetMacro(DiagonalStiffness, double);
  vtkSetMacro(PinnedCorners, int);
  vtkGetMacro(PinnedCorners, int);

protected:
  vtkSoftBodyCloth();
  ~vtkSoftBodyCloth() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  double Origin[3] = { -0.5, 0.0, 1.0 };
  double Point1[3] = { 0.5, 0.0, 1.0 };
  double Point2[3] = { -0.5, 1.0, 1.0 };
  int Resolution[2] = { 50, 50 };
  double TotalMass = 0.1;
  double DiagonalStiffness = 0.01;
  int PinnedCorners = POINT2_CORNERS;

private:
  vtkSoftBodyCloth(const vtkSoftBodyCloth&) = delete;
  void operator=(const vtkSoftBodyCloth&) = delete;
};

#endif

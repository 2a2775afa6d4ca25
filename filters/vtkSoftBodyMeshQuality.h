/**
 * @class   vtkSoftBodyMeshQuality
 * @brief   Reports how fit a tetrahedral mesh is for the mass-spring soft body, before simulating.
 *
 * The input is a vtkUnstructuredGrid of tetrahedra (other cells are an error, as in
 * vtkSoftBodyFilter). The outputs are
 *
 * - port 0 ("Mesh"): the input with cell arrays "Volume" (signed) [m^3] and "AspectRatio" [-]
 *   (from vtkMeshQuality), "MinDihedralAngle" [degrees] (from core: ParaView 5.11's
 *   vtkMeshQuality::TetMinAngle misses two of the six angles), "Inverted", "Degenerate"
 *   and "Sliver" (0/1), and point array "InverseMass" [1/kg]: the untruncated inverse mass the
 *   Soft Body filter would give each point with the same material;
 * - port 1 ("Histograms"): a vtkTable of NumberOfBins rows with bin centers and counts of the
 *   point inverse masses, the tet volumes and the edge lengths: columns "InverseMass",
 *   "InverseMassCount", "Volume", "VolumeCount", "EdgeLength", "EdgeLengthCount".
 *
 * Both outputs carry the summary as field data (one value each): "InvertedTets",
 * "DegenerateTets", "SliverTets", "BadIndexTets", "MinDihedralAngle", "SliverAngle",
 * "TotalMass", "StableTimeStep", "SuggestedMaxInverseMass", "TruncatedPoints",
 * "TruncatedTotalMass", "TruncatedStableTimeStep", "StableStepGain", plus string arrays
 * "Integrator" and "Warnings". Field data rather than a third port: the numbers travel with
 * whichever output the user looks at, the spreadsheet view shows them, and the histogram table
 * stays purely columnar so the bar chart plots only histogram columns.
 *
 * A tet is a sliver when its smallest dihedral angle is below SliverAngle (default 5 degrees)
 * and it is not degenerate; degenerate (|V| below 1e-8 of the mean) and inverted tets follow
 * softbody::inspectTetMesh. The numbers come from softbody::computeMassSpringQuality, which
 * uses the simulation's own mass distribution and stability estimate.
 *
 * The material properties have the Soft Body filter's names and meanings, so values can be
 * copied between the two.
 */
#ifndef vtkSoftBodyMeshQuality_h
#define vtkSoftBodyMeshQuality_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkSoftBodyFilter.h" // for vtkSoftBodyFilter::Parameters
#include "vtkUnstructuredGridAlgorithm.h"

class SOFTBODYFILTERS_EXPORT vtkSoftBodyMeshQuality : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkSoftBodyMeshQuality* New();
  vtkTypeMacro(vtkSoftBodyMeshQuality, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Integrator whose stable step is reported, with vtkSoftBodyFilter's values: EULER (0),
   * MIDPOINT (1), VERLET (2), EULER_CROMER (3, default).
   */
  vtkSoftBodyParameterMacro(Integrator, int);
  ///@}

  ///@{
  /**
   * Material, exactly as in vtkSoftBodyFilter: MaterialModel SPRING_NETWORK (0, default),
   * COROTATED (1) or STABLE_NEO_HOOKEAN (2), whose stable step the report gives (the
   * finite-element models' from their rest stiffness, as the Soft Body filter's set-up);
   * MaterialMode PHYSICAL (0, default) uses
   * YoungsModulus [Pa], PoissonRatio [-], Density [kg/m^3] and DampingTime [s]; RAW_CONSTANTS
   * (1) uses DistanceStiffness [J], DistanceDamping [J s], VolumeStiffness [J], VolumeDamping
   * [J s] and TotalMass [kg]. MassDistribution: AVERAGE_INCIDENT_VOLUME (0, default) or
   * LUMPED_VOLUME (1).
   */
  vtkSoftBodyParameterMacro(MaterialModel, int);
  vtkSoftBodyParameterMacro(MaterialMode, int);
  vtkSoftBodyParameterMacro(YoungsModulus, double);
  vtkSoftBodyParameterMacro(PoissonRatio, double);
  vtkSoftBodyParameterMacro(Density, double);
  vtkSoftBodyParameterMacro(DampingTime, double);
  vtkSoftBodyParameterMacro(DistanceStiffness, double);
  vtkSoftBodyParameterMacro(DistanceDamping, double);
  vtkSoftBodyParameterMacro(VolumeStiffness, double);
  vtkSoftBodyParameterMacro(VolumeDamping, double);
  vtkSoftBodyParameterMacro(TotalMass, double);
  vtkSoftBodyParameterMacro(MassDistribution, int);
  ///@}

  ///@{
  /**
   * SliverAngle [degrees]: tets whose smallest dihedral angle is below it are slivers (default 5).
   * NumberOfBins: bins of each histogram (default 32, >= 1).
   * TruncationMassBudget [%]: the suggested MaxInverseMass is the lowest inverse-mass cap that
   * adds at most this percentage to the body's mass (default 1): the largest stable-step gain
   * that costs no more mass than that.
   */
  vtkSetMacro(SliverAngle, double);
  vtkGetMacro(SliverAngle, double);
  vtkSetMacro(NumberOfBins, int);
  vtkGetMacro(NumberOfBins, int);
  vtkSetMacro(TruncationMassBudget, double);
  vtkGetMacro(TruncationMassBudget, double);
  ///@}

protected:
  vtkSoftBodyMeshQuality();
  ~vtkSoftBodyMeshQuality() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  // The properties shared with the Soft Body filter, with its defaults and its conversion.
  vtkSoftBodyFilter::Parameters P;
  double SliverAngle = 5.0;
  int NumberOfBins = 32;
  double TruncationMassBudget = 1.0;

private:
  vtkSoftBodyMeshQuality(const vtkSoftBodyMeshQuality&) = delete;
  void operator=(const vtkSoftBodyMeshQuality&) = delete;
};

#endif

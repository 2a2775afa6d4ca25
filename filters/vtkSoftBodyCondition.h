/**
 * @class   vtkSoftBodyCondition
 * @brief   One load or boundary condition on a region of a body, for the Soft Body filter's
 *          Conditions input.
 *
 * The input is the body (the mesh given to the Soft Body filter, or anything with the same
 * points). The condition's set is chosen by Region: a point or cell array (non-zero = in the
 * set; a cell array selects the points of its cells), a box, a sphere, the half-space on the
 * normal side of a plane, or every point. In ParaView each region is drawn and edited with its
 * 3D widget. ConditionType says what the set does (core/scene/conditions.h):
 * - FIXED: the chosen components (HeldComponents; a roller holds one) stay at rest;
 * - PRESCRIBED: the set moves rigidly, at time t to c + R(s theta)(X - c) + s Translation, with
 *   R the rotation by RotationAngle (degrees) about RotationAxis through RotationCenter and s
 *   the Profile's factor;
 * - FORCE: a Force in newtons, spread over the set by mass or by area, or on each point;
 * - PRESSURE: a Pressure in pascals on the body's boundary faces whose corners are all in the
 *   set, along their outward normals (positive inflates), following the deformed faces;
 * - PULL: a spring of PullStiffness (N/m) from the set's centroid to PullTarget (a handle).
 * Profile scales the motion or the load over time: constant, a ramp over ProfileTime seconds,
 * a sinusoid of period ProfileTime, or piecewise linear through Keyframes (time, factor).
 *
 * Output (vtkPolyData): the set's points as vertices, with point array InputPointId (the
 * input's point numbers), and field data describing the condition, which the Soft Body filter
 * reads (vtkSoftBodyConditionCodec). The Soft Body filter finds the set among its own points by
 * position, so the condition may sit on the same source as the body or on any filter that keeps
 * its points (Extract Selection of the body's points, for one picked in the GUI).
 */
#ifndef vtkSoftBodyCondition_h
#define vtkSoftBodyCondition_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string>
#include <vector>

class SOFTBODYFILTERS_EXPORT vtkSoftBodyCondition : public vtkPolyDataAlgorithm
{
public:
  static vtkSoftBodyCondition* New();
  vtkTypeMacro(vtkSoftBodyCondition, vtkPolyDataAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ConditionTypes
  {
    FIXED = 0,
    PRESCRIBED = 1,
    FORCE = 2,
    PRESSURE = 3,
    PULL = 4
  };
  enum Regions
  {
    REGION_ARRAY = 0,
    REGION_BOX = 1,
    REGION_SPHERE = 2,
    REGION_HALF_SPACE = 3,
    REGION_ALL = 4
  };
  enum ForceSpreads
  {
    BY_MASS = 0,
    BY_AREA = 1,
    PER_POINT = 2
  };
  enum Profiles
  {
    CONSTANT = 0,
    RAMP = 1,
    SINUSOID = 2,
    KEYFRAMES = 3
  };

  /// Quoted in every message about the condition and in the output's field data names.
  vtkSetStdStringFromCharMacro(ConditionName);
  vtkGetCharFromStdStringMacro(ConditionName);
  vtkSetMacro(ConditionType, int);
  vtkGetMacro(ConditionType, int);

  vtkSetMacro(Region, int);
  vtkGetMacro(Region, int);
  // REGION_ARRAY: the array is the algorithm's input array 0 (SetInputArrayToProcess).
  /// REGION_BOX: the unit cube scaled by BoxScale, rotated by BoxRotation (degrees about z,
  /// then x, then y, as ParaView's box widget), moved to BoxPosition.
  vtkSetVector3Macro(BoxPosition, double);
  vtkGetVector3Macro(BoxPosition, double);
  vtkSetVector3Macro(BoxRotation, double);
  vtkGetVector3Macro(BoxRotation, double);
  vtkSetVector3Macro(BoxScale, double);
  vtkGetVector3Macro(BoxScale, double);
  vtkSetVector3Macro(SphereCenter, double);
  vtkGetVector3Macro(SphereCenter, double);
  vtkSetMacro(SphereRadius, double);
  vtkGetMacro(SphereRadius, double);
  /// REGION_HALF_SPACE: points on the side PlaneNormal points to (on the plane included).
  vtkSetVector3Macro(PlaneOrigin, double);
  vtkGetVector3Macro(PlaneOrigin, double);
  vtkSetVector3Macro(PlaneNormal, double);
  vtkGetVector3Macro(PlaneNormal, double);

  /// FIXED and PRESCRIBED: 1 for each of x, y, z that is held.
  vtkSetVector3Macro(HeldComponents, int);
  vtkGetVector3Macro(HeldComponents, int);
  vtkSetVector3Macro(Translation, double);
  vtkGetVector3Macro(Translation, double);
  vtkSetVector3Macro(RotationAxis, double);
  vtkGetVector3Macro(RotationAxis, double);
  vtkSetVector3Macro(RotationCenter, double);
  vtkGetVector3Macro(RotationCenter, double);
  vtkSetMacro(RotationAngle, double); ///< [degrees]
  vtkGetMacro(RotationAngle, double);
  vtkSetVector3Macro(Force, double); ///< [N]
  vtkGetVector3Macro(Force, double);
  vtkSetMacro(ForceSpread, int);
  vtkGetMacro(ForceSpread, int);
  vtkSetMacro(Pressure, double); ///< [Pa]
  vtkGetMacro(Pressure, double);
  vtkSetVector3Macro(PullTarget, double); ///< [m]
  vtkGetVector3Macro(PullTarget, double);
  vtkSetMacro(PullStiffness, double); ///< [N/m]
  vtkGetMacro(PullStiffness, double);

  vtkSetMacro(Profile, int);
  vtkGetMacro(Profile, int);
  vtkSetMacro(ProfileTime, double); ///< ramp duration or sinusoid period [s]
  vtkGetMacro(ProfileTime, double);
  /// KEYFRAMES: (time [s], factor) pairs in increasing time.
  void AddKeyframe(double time, double factor);
  void RemoveAllKeyframes();

protected:
  vtkSoftBodyCondition();
  ~vtkSoftBodyCondition() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

private:
  vtkSoftBodyCondition(const vtkSoftBodyCondition&) = delete;
  void operator=(const vtkSoftBodyCondition&) = delete;

  std::string ConditionName = "Condition";
  int ConditionType = FIXED;
  int Region = REGION_BOX;
  double BoxPosition[3] = { 0.0, 0.0, 0.0 };
  double BoxRotation[3] = { 0.0, 0.0, 0.0 };
  double BoxScale[3] = { 1.0, 1.0, 1.0 };
  double SphereCenter[3] = { 0.0, 0.0, 0.0 };
  double SphereRadius = 0.5;
  double PlaneOrigin[3] = { 0.0, 0.0, 0.0 };
  double PlaneNormal[3] = { 0.0, 0.0, -1.0 };
  int HeldComponents[3] = { 1, 1, 1 };
  double Translation[3] = { 0.0, 0.0, 0.0 };
  double RotationAxis[3] = { 0.0, 0.0, 1.0 };
  double RotationCenter[3] = { 0.0, 0.0, 0.0 };
  double RotationAngle = 0.0;
  double Force[3] = { 0.0, 0.0, 0.0 };
  int ForceSpread = BY_MASS;
  double Pressure = 0.0;
  double PullTarget[3] = { 0.0, 0.0, 0.0 };
  double PullStiffness = 100.0;
  int Profile = CONSTANT;
  double ProfileTime = 1.0;
  std::vector<double> KeyframeTimes, KeyframeFactors;
};

#endif

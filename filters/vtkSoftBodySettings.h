/**
 * @file   vtkSoftBodySettings.h
 * @brief  The one place where the Soft Body filters' properties become core settings.
 *
 * vtkSoftBodyFilter (Mass-Spring and PBD/XPBD) and vtkSoftBodyMeshQuality hold their properties
 * in a vtkSoftBodyFilter::Parameters; these functions turn it into the core settings the
 * selected method reads. Enumerations out of their lists and time-grid values are refused
 * here; every other range is checked by core when the simulation is built, so each refusal is
 * said once, with the value the user gave.
 */
#ifndef vtkSoftBodySettings_h
#define vtkSoftBodySettings_h

#include "vtkIndent.h"
#include "vtkSoftBodyFilter.h"

#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/pbd/pbd_settings.h"

#include <string>

/**
 * What a Soft Body simulation is built from, apart from the input: only the settings of the
 * selected method are filled (the others stay default), so this is also the frame cache's key:
 * changing a property the method ignores leaves it equal and keeps the cache.
 */
struct vtkSoftBodyCoreSettings
{
  int Method = vtkSoftBodyFilter::MASS_SPRING;
  int Device = vtkSoftBodyFilter::DEVICE_CPU; ///< as asked for (Mass-Spring only; PBD runs on the CPU)
  double FrameInterval = 0.0;                 ///< frames are cached on this grid [s]
  std::string PinnedPointsArray;              ///< empty: nothing pinned
  /// Cell arrays of per-cell YoungsModulus, PoissonRatio, Density; empty: uniform.
  std::string YoungsModulusArray, PoissonRatioArray, DensityArray;
  /// The initial state (vtkSoftBodyInitialState); empty array names: none.
  struct InitialState
  {
    softbody::Vec3 velocity{ 0.0, 0.0, 0.0 }; ///< [m/s]
    softbody::Vec3 spin{ 0.0, 0.0, 0.0 };     ///< [rad/s] about the centre of mass
    std::string velocityArray, displacementArray;
    bool operator==(const InitialState&) const = default;
  } Initial;
  /// The Conditions input on the body (vtkSoftBodyConditionInput), in its point numbers.
  std::vector<softbody::Condition> Conditions;

  /// The body's material, for every method (PBD and XPBD fill only what they read: density and
  /// mass distribution, and under XPBD from Young's modulus the model, E and nu).
  softbody::MaterialSettings Material;

  // Mass-Spring
  softbody::SceneSettings Scene;

  // PBD / XPBD
  softbody::PbdSettings Pbd;

  bool operator==(const vtkSoftBodyCoreSettings&) const = default;

  /// The selected method's scene: what its rules (core's Scene::floorActive(),
  /// CollisionSettings::on(), bodiesCollide()) are asked of.
  softbody::Scene& SelectedScene()
  {
    return this->Method == vtkSoftBodyFilter::MASS_SPRING ? static_cast<softbody::Scene&>(this->Scene)
                                                          : static_cast<softbody::Scene&>(this->Pbd);
  }
  const softbody::Scene& SelectedScene() const
  {
    return this->Method == vtkSoftBodyFilter::MASS_SPRING
      ? static_cast<const softbody::Scene&>(this->Scene)
      : static_cast<const softbody::Scene&>(this->Pbd);
  }
};

namespace vtkSoftBodySettings
{
/// The properties' defaults (the struct's, with the raw-mode constants from core).
vtkSoftBodyFilter::Parameters DefaultParameters();

/// The core settings for the selected method. Throws softbody::InvalidInputError for an
/// enumeration value out of its list, a bad time grid or Cache memory limit (quoting the value).
vtkSoftBodyCoreSettings Convert(const vtkSoftBodyFilter::Parameters& p);

/// EndTime, FrameInterval (and their frame count) and CacheMemoryLimit; throws as Convert.
void ValidateTimes(const vtkSoftBodyFilter::Parameters& p);

/// The mass-spring material (Mass-Spring, and Mesh Quality's stability report).
softbody::MaterialSettings Material(const vtkSoftBodyFilter::Parameters& p);

/// The scene shared by every method: Gravity, Floor, FloorOrigin, FloorNormal and the contact
/// settings; the floor plane filled only where the floor is active (so only then in the key).
softbody::Scene Scene(const vtkSoftBodyFilter::Parameters& p);

/// The contact settings shared by every method (Collisions, BroadPhase, CollisionMargin,
/// StaticFriction, DynamicFriction, Restitution); the mode refused when out of its list.
softbody::CollisionSettings Collisions(const vtkSoftBodyFilter::Parameters& p);

/// The explicit integrator of the Integrator property.
softbody::Integrator Integrator(int integrator);

/// PrintSelf's lines for the material properties (both filters that have them).
void PrintMaterial(ostream& os, vtkIndent indent, const vtkSoftBodyFilter::Parameters& p);

/// Warnings about accepted but noteworthy values (e.g. CacheMemoryLimit 0 turns caching off).
std::vector<std::string> Warnings(const vtkSoftBodyFilter::Parameters& p);

/// More frames than this is a typo (e.g. FrameInterval in ms), not a plan.
constexpr double MaxFrames = 1.0e6;
}

#endif

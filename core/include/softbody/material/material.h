// Material parameters and their conversion to per-spring and per-tet constants.
//
// The model is the mass-spring system of Teschner et al. 2004 ("A versatile and robust model
// for geometrically complex deformable solids") as used by the tetrahedral mass-spring thesis:
//   distance preservation, per edge:  C_D = (l - l0) / l0,   E_D = k_D / 2 * C_D^2
//   volume preservation, per tet:     C_V = (V - V0) / V0,   E_V = k_V / 2 * C_V^2
//   force on point i:  f_i = -(k C + k_d dC/dt) dC/dp_i
// k_D and k_V are energies [J]; k_d are [J s].
//
// Physical mode derives them from Young's modulus E, Poisson ratio nu and a Rayleigh
// (stiffness-proportional) damping time beta. For small strains an isotropic network of
// springs with sum_e k_D,e = kappa * V behaves like a linear solid with Lame parameters
// lambda = mu = kappa / 15 (average of n_i n_j n_k n_l over directions), i.e. nu = 1/4.
// So springs carry the shear modulus: k_D,e = 15 mu V_e with V_e = (sum of the volumes of the
// tets around e) / 6, and the volume term adds the missing lambda - mu >= 0 (C_V = tr(eps) for
// small strain): k_V,t = (lambda - mu) V_t. A network cannot express nu < 1/4; it is clamped
// there with a warning. Damping: k_d = beta * k, so a mode of angular frequency w gets the
// damping ratio beta * w / 2.
#pragma once

#include "softbody/mesh/topology.h"

#include <string>
#include <vector>

namespace softbody
{

enum class MaterialMode
{
  Physical, ///< Young's modulus, Poisson ratio, density, damping time
  Raw       ///< the thesis's constants k_D, k_V, damping and total mass, taken as they are
};

/// The constitutive model of a tet body. The spring network is the thesis's model (above); the
/// two continuum models are finite elements on linear tets (tet_elasticity.h), whose E and nu
/// mean what they mean in a paper: any nu in (-1, 0.5), nothing clamped.
enum class MaterialModel
{
  SpringNetwork,   ///< springs and volume terms (Teschner et al. 2004)
  Corotated,       ///< fixed corotated linear elasticity (Stomakhin et al. 2012)
  StableNeoHookean, ///< Stable Neo-Hookean (Smith, de Goes and Kim 2018)
  Count             ///< not a model: how many there are (a new one goes above it)
};

const char* materialModelName(MaterialModel model);
inline bool isContinuum(MaterialModel model) { return model != MaterialModel::SpringNetwork; }

/// How a continuum model's tets hold their volume (material/nodal_pressure.h).
enum class VolumetricFormulation
{
  PerTet,      ///< each tet its own volume ratio: linear tets, which lock as nu nears 0.5
  NodalAverage ///< the volume ratio averaged at the points (Bonet and Burton 1998): no locking
};

enum class MassDistribution
{
  AverageIncidentVolume, ///< m_i proportional to the mean volume of the tets around i (thesis)
  LumpedVolume           ///< m_i proportional to a quarter of the volume of the tets around i
};

struct PhysicalMaterial
{
  double youngsModulus = 1.0e5; ///< E [Pa]; soft rubber
  /// nu: spring network [0, 0.5), below 0.25 raised to 0.25 with a warning (the smallest a
  /// network represents); continuum models (-1, 0.5), taken as given.
  double poissonRatio = 0.3;
  double density = 1100.0;      ///< rho [kg/m^3]
  double dampingTime = 2.0e-3;  ///< beta [s]: stiffness-proportional damping
  bool operator==(const PhysicalMaterial&) const = default;
};

struct RawConstants
{
  double distanceStiffness = 100.0; ///< k_D [J]
  double distanceDamping = 0.1;     ///< k_D,d [J s]
  double volumeStiffness = 100.0;   ///< k_V [J]
  double volumeDamping = 0.1;       ///< k_V,d [J s]
  double totalMass = 1.0;           ///< [kg]
  bool operator==(const RawConstants&) const = default;
};

/// Values per tet (in the mesh's tet order) that replace the uniform PhysicalMaterial's; each
/// vector is empty (uniform) or has one value per tet. Two tissues in one mesh, or one value per
/// Gmsh physical group, come in this way.
struct CellMaterial
{
  std::vector<double> youngsModulus; ///< E [Pa]
  std::vector<double> poissonRatio;  ///< nu
  std::vector<double> density;       ///< rho [kg/m^3]
  bool empty() const { return youngsModulus.empty() && poissonRatio.empty() && density.empty(); }
  bool operator==(const CellMaterial&) const = default;
};

struct MaterialSettings
{
  MaterialModel model = MaterialModel::SpringNetwork;
  MaterialMode mode = MaterialMode::Physical; ///< continuum models need Physical
  PhysicalMaterial physical;
  RawConstants raw;
  MassDistribution massDistribution = MassDistribution::AverageIncidentVolume;
  /// Continuum models only; NodalAverage for nearly incompressible materials.
  VolumetricFormulation volumetric = VolumetricFormulation::PerTet;
  /// Largest allowed inverse mass [1/kg]; larger ones are truncated (the point gets heavier).
  /// 0 disables truncation.
  double maxInverseMass = 0.0;
  CellMaterial cells; ///< per-tet values (Physical mode only)
  bool operator==(const MaterialSettings&) const = default;

  /// The physical material of tet t: the uniform one with its per-cell values put in.
  PhysicalMaterial physicalOf(std::size_t t) const
  {
    PhysicalMaterial m = physical;
    m.youngsModulus = cells.youngsModulus.empty() ? m.youngsModulus : cells.youngsModulus[t];
    m.poissonRatio = cells.poissonRatio.empty() ? m.poissonRatio : cells.poissonRatio[t];
    m.density = cells.density.empty() ? m.density : cells.density[t];
    return m;
  }
};

/// Per-element constants in the units the force kernels use directly.
struct ElementConstants
{
  std::vector<double> restLength;       ///< l0 per edge [m]
  std::vector<double> springStiffness;  ///< k_D / l0^2 per edge [N/m]
  std::vector<double> springDamping;    ///< k_D,d / l0^2 per edge [N s/m]
  std::vector<double> restVolume;       ///< V0 per tet [m^3] (positive)
  std::vector<double> volumeStiffness;  ///< k_V / V0^2 per tet [N/m^5]
  std::vector<double> volumeDamping;    ///< k_V,d / V0^2 per tet [N s/m^5]
  bool hasVolumeTerm = false;           ///< any nonzero volume stiffness or damping
  double minDampingTime = 0.0;          ///< smallest k_d / k over elements [s]
  double maxDampingTime = 0.0;          ///< largest k_d / k over elements [s]
};

/// Throws InvalidInputError for out-of-range parameters; appends warnings (e.g. clamped nu).
/// `tetCount` checks the per-cell values' sizes (each value is checked and a refusal names the
/// cell).
void validateMaterial(const MaterialSettings& material, std::vector<std::string>& warnings,
  std::size_t tetCount = 0);

/// The per-cell values alone (validateMaterial's first part): sizes against `tetCount`, then each
/// value, a refusal naming the first bad cell; warnings for raised or nearly incompressible ones.
void validateCells(const MaterialSettings& material, std::size_t tetCount,
  std::vector<std::string>& warnings);

/// The mass of each tet, rho_t V_t [kg] (what distributeMass spreads over the points).
std::vector<double> tetMasses(const MaterialSettings& material, const std::vector<double>& restVolume);

/// Total mass [kg] the material gives a body of the given rest volume (uniform density).
double totalMassOf(const MaterialSettings& material, double restVolume);

ElementConstants computeElementConstants(const Topology& topology,
  const std::vector<Vec3>& restPositions, const MaterialSettings& material,
  std::vector<std::string>& warnings);

} // namespace softbody

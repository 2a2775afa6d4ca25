// Position-based dynamics (Mueller et al. 2007) and XPBD (Macklin et al. 2016) on particles
// linked by distance constraints (tet edges, cloth and lattice links) and tet volume
// constraints, with pins, a floor with friction and restitution, and breakable and plastic links.
#pragma once

#include "softbody/common/floor_plane.h"
#include "softbody/material/material.h"    // MassDistribution
#include "softbody/pbd/pbd_constraints.h"
#include "softbody/pbd/pbd_solvers.h"
#include "softbody/common/simulation.h"
#include "softbody/mesh/tet_mesh.h"
#include "softbody/mesh/topology.h"

#include <array>
#include <string>
#include <vector>

namespace softbody
{

enum class PbdFormulation
{
  Pbd, ///< stiffness k in [0, 1] per constraint type, iteration-count corrected
  Xpbd ///< compliance alpha (inverse stiffness, physical units) per constraint type
};

enum class PbdSolver
{
  GaussSeidel, ///< SOR when relaxation != 1
  Jacobi,      ///< averaged Jacobi with relaxation
  ParallelGaussSeidel
};

enum class PbdPrediction
{
  SymplecticEuler, ///< v += h a; p = x + h v
  Verlet           ///< p = x + h v + h^2 a, v the position difference of the last step
};

/// Stiffness (PBD) or compliance (XPBD) of one constraint type.
struct ConstraintMaterial
{
  double stiffness = 1.0;  ///< PBD, in [0, 1]
  double compliance = 0.0; ///< XPBD, >= 0; units: inverse of the constraint's stiffness
};

struct PbdSettings
{
  PbdFormulation formulation = PbdFormulation::Xpbd;
  PbdSolver solver = PbdSolver::GaussSeidel;
  PbdPrediction prediction = PbdPrediction::SymplecticEuler;
  /// [s]; 0 = automatic: steps of at most kDefaultPbdStep (PBD is stable at any step; the step
  /// sets the accuracy, not the stability).
  double timeStep = 0.0;
  int substeps = 1;   ///< each step runs `substeps` substeps of `iterations` iterations each
  int iterations = 10; ///< per substep; the cap when residualTolerance > 0
  /// Stop iterating once sqrt(sum of squared residuals) is below this [constraint units]; 0 runs
  /// the fixed count. Checking costs one extra evaluation pass per iteration.
  double residualTolerance = 0.0;
  double relaxation = 1.0; ///< SOR factor (Gauss-Seidel) or Jacobi's relaxation, in (0, 2)
  Vec3 gravity{ 0.0, 0.0, -9.81 };
  /// Velocity damping rate [1/s]: v *= max(0, 1 - damping h) each substep.
  double damping = 0.0;

  bool floorEnabled = false;
  FloorPlane floor;
  double particleRadius = 0.0; ///< particles keep this distance from the floor [m]
  double friction = 0.0;       ///< Coulomb coefficient at the floor
  double restitution = 0.0;    ///< in [0, 1]: the normal speed kept after a bounce

  ConstraintMaterial links;       ///< distance: compliance in m/N
  ConstraintMaterial volumes;     ///< tet volume (C = V - V0 in m^3): compliance in m^3/Pa
  ConstraintMaterial attachments; ///< soft pins: compliance in m/N

  /// XPBD only: derive every tet edge's and tet's compliance from Young's modulus and Poisson's
  /// ratio, as the mass-spring model derives its stiffnesses (k_D = 15 mu V_e, k_V = (lambda -
  /// mu) V_t, material.h), so both methods minimize the same elastic energy and a converged
  /// XPBD body rests where the mass-spring one does. Explicit links keep `links.compliance`.
  struct Elasticity
  {
    bool enabled = false;
    double youngsModulus = 1.0e5; ///< [Pa]
    double poissonRatio = 0.3;
  } elasticity;

  /// A link breaks when |l - l0| / l0 (l0 its original rest length) passes this; 0 = unbreakable.
  double breakingStrain = 0.0;
  /// Plastic links: past this strain (relative to the current rest length) the rest length
  /// creeps toward the current length at `plasticCreep` [1/s]; 0 = elastic.
  double plasticYield = 0.0;
  double plasticCreep = 0.0;

  InvertedTetPolicy invertedTets = InvertedTetPolicy::Reorient;
};

constexpr double kDefaultPbdStep = 1.0 / 120.0;

struct PbdBody
{
  std::vector<Vec3> points; ///< rest positions [m]
  std::vector<Tet> tets;    ///< may be empty; each contributes its volume and its 6 edges
  std::vector<std::array<std::int32_t, 2>> links; ///< explicit distance links (line cells)
  std::vector<double> linkStiffnessScale;         ///< empty, or a factor per explicit link
  /// Per-point mass [kg]; empty = density times the tet volumes, distributed as chosen.
  std::vector<double> pointMass;
  double density = 1000.0; ///< [kg/m^3]
  MassDistribution massDistribution = MassDistribution::AverageIncidentVolume;
  /// Empty or one flag per point. Pinned points are fixed (inverse mass 0) when the attachment
  /// is hard (stiffness 1 / compliance 0), otherwise attached to their rest position.
  std::vector<char> pinned;
};

/// Convergence of the last step: iterations run and the residual after each.
struct PbdConvergence
{
  int iterations = 0;
  double residual = 0.0;              ///< after the last iteration
  std::vector<double> residualHistory; ///< after each iteration of the last substep
};

class PbdSimulation final : public Simulation
{
public:
  /// Validates and prepares; throws InvalidInputError with a user-facing message.
  PbdSimulation(PbdBody body, const PbdSettings& settings);

  AdvanceStatus advance(double endTime, const ProgressCallback& progress = {}) override;
  const DynamicState& state() const override { return State; }
  void restoreState(const DynamicState& snapshot) override;

  const std::vector<Vec3>& restPositions() const override { return Rest; }
  const std::vector<double>& inverseMasses() const override { return InverseMass; }
  double totalMass() const override { return TotalMass; }
  std::vector<double> tetVolumeRatios() const override;
  double stepSize() const override { return Step; }
  double estimatedStableStep() const override { return 0.0; }
  const std::vector<std::string>& warnings() const override { return Warnings; }
  std::vector<StageTiming> stageTimings() const override;

  /// Runs exactly one step of size h (tests and benchmarks drive the solver with this).
  void step(double h);
  /// Records the residual after every iteration of every following step (benchmarks); by
  /// default only the last step of each advance() records it.
  void setRecordResidualsEveryStep(bool record) { RecordEveryStep = record; }
  const PbdConvergence& convergence() const { return Convergence; }

  /// The batches as stored: in input order, except with the parallel solver, which stores them
  /// color by color (use linkBroken / tetBroken to ask about an input link or tet).
  const DistanceBatch& links() const { return Links; }
  const VolumeBatch& volumes() const { return Volumes; }
  /// Links in input order are the tet edges (topology order), then the explicit links: explicit
  /// link j is link explicitLinkOffset() + j.
  std::size_t explicitLinkOffset() const { return ExplicitLinkOffset; }
  bool linkBroken(std::size_t link) const;
  bool tetBroken(std::size_t tet) const; ///< tet k in input order
  std::size_t brokenLinkCount() const;
  std::size_t colorCount() const; ///< colors of the link batch (parallel Gauss-Seidel)

private:
  /// Indices into StageSeconds, in step order (the timings are split over several .cpp files).
  enum StageIndex
  {
    kPredict,
    kSolve,
    kResidual,
    kVelocities,
    kContacts,
    kLinks,
    kDivergenceCheck,
    kStageCount
  };

  void substep(double h, bool recordResiduals);
  void prepareParameters(double h);
  void predict(double h);
  void solve(bool recordResiduals);
  void sweep();
  double residual() const;
  void projectFloor();
  void updateVelocities(double h);
  void applyContactResponse(double h);
  void updateLinks(double h);
  void markBrokenTets();
  void storeLinksAndVolumesByColor();
  void setComplianceFromElasticity(const Topology& topology, const std::vector<Vec3>& rest);
  void checkDivergence() const;

  PbdSettings Settings;
  std::vector<Vec3> Rest;
  std::vector<double> InverseMass;
  std::vector<char> Movable;
  double TotalMass = 0.0;
  DistanceBatch Links;
  VolumeBatch Volumes;
  AttachmentBatch Attachments;
  BatchSchedule LinkSchedule, VolumeSchedule, AttachmentSchedule;
  Csr TetEdges; ///< tet -> its 6 link indices, to mark tets of broken links
  std::size_t ExplicitLinkOffset = 0;
  std::vector<std::int32_t> LinkSlot, VolumeSlot; ///< input index -> storage index (empty: same)
  DynamicState State;
  double Step = 0.0;
  std::vector<std::string> Warnings;
  bool RecordEveryStep = false;
  PbdConvergence Convergence;

  // Per-step scratch
  std::vector<Vec3> Predicted;
  std::vector<Vec3> VelocityBefore; ///< velocity entering the solve (for restitution)
  std::vector<unsigned char> InContact;
  std::vector<Vec3> JacobiScratch;
  double ParametersStep = -1.0;
  mutable std::vector<double> StageSeconds;
};

} // namespace softbody

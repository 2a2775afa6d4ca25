#include "softbody/massspring/static_solve.h"

#include "softbody/common/errors.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace softbody
{

namespace
{

/// "(0.6, 0, 0.8)": a unit direction (or a line's) for a message.
std::string direction(const Vec3& v)
{
  std::ostringstream out;
  Vec3 u = v.normalized();
  // A line's direction has no sign: show the one whose first clear component is positive.
  for (int k = 0; k < 3; ++k)
  {
    if (std::abs(u(k)) > 1e-6)
    {
      u = u(k) < 0.0 ? Vec3(-u) : u;
      break;
    }
  }
  const auto tidy = [](double x) { return std::abs(x) < 1e-6 ? 0.0 : x; };
  out << std::setprecision(3) << '(' << tidy(u.x()) << ", " << tidy(u.y()) << ", " << tidy(u.z()) << ')';
  return out.str();
}

} // namespace

std::string staticHoldProblem(const std::vector<Vec3>& positions, const PointMasses& masses,
  const std::vector<AxisMask>& heldAxes)
{
  const std::string remedy = " Hold it where it is supported: a Fixed Soft Body Condition on "
                             "that region (or PinnedPointsArray; rollers, with some of "
                             "HeldComponents, on symmetry planes), or use Implicit Euler, which "
                             "needs no support.";
  // Each held component (point i, axis a) asks every rigid velocity v = t + w x (p_i - c) to
  // have v_a = 0: one row (e_a, (p_i - c) x e_a) . (t, w). The supports hold the body when
  // these rows span all six rigid motions; a null vector of their Gram matrix is a motion they
  // leave free. Positions are taken about the centroid over the body's size, so the rows of
  // translations and turns are of one scale.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : positions)
  {
    centroid += p;
  }
  centroid /= double(std::max<std::size_t>(positions.size(), 1));
  double size = 0.0;
  for (const Vec3& p : positions)
  {
    size = std::max(size, (p - centroid).norm());
  }
  size = size > 0.0 ? size : 1.0;
  Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
  std::size_t fixedPoints = 0, heldComponents = 0;
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    const bool fixed = masses.inverseMass[i] == 0.0;
    const AxisMask held = fixed ? kAllAxes : (i < heldAxes.size() ? heldAxes[i] : AxisMask(0));
    fixedPoints += fixed ? 1 : 0;
    const Vec3 d = (positions[i] - centroid) / size;
    for (int axis = 0; axis < 3; ++axis)
    {
      if (held & (1u << axis))
      {
        Eigen::Matrix<double, 6, 1> row;
        const Vec3 e = Vec3::Unit(axis);
        row << e, d.cross(e);
        gram += row * row.transpose();
        ++heldComponents;
      }
    }
  }
  if (heldComponents == 0)
  {
    return "Integrator Static needs a body held still, but it has 0 fixed points and no held "
           "components: a free body can move or turn and has no static equilibrium." + remedy;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> modes(gram);
  const double largest = modes.eigenvalues()(5);
  if (modes.eigenvalues()(0) > 1e-12 * largest)
  {
    return {};
  }
  const Eigen::Matrix<double, 6, 1> free = modes.eigenvectors().col(0);
  const Vec3 translation = free.head<3>(), turn = free.tail<3>();
  const std::string supports = "its supports (" + std::to_string(fixedPoints) + " fixed points, " +
    std::to_string(heldComponents) + " held components in all)";
  std::string motion;
  if (turn.norm() < 1e-6 * translation.norm())
  {
    motion = "move along " + direction(translation);
  }
  else
  {
    // The line the body turns about: where t + w x (p - c) / size vanishes.
    const Vec3 through = centroid + size * turn.cross(translation) / turn.squaredNorm();
    std::ostringstream point;
    point << std::setprecision(4) << '(' << through.x() << ", " << through.y() << ", " << through.z() << ')';
    motion = "turn about the line along " + direction(turn) + " through " + point.str() +
      " m (points held on one line cannot stop that)";
  }
  return "Integrator Static needs a body held still, but " + supports + " leave it free to " +
    motion + ": it has no static equilibrium." + remedy;
}

StaticStepper::StaticStepper(const Topology& topology, const BodyElements& elements,
  const PointMasses& masses, const std::vector<Vec3>& restPositions, const SceneSettings& scene,
  const std::vector<Vec3>& positions, const BoundaryConditions* conditions)
{
  static const std::vector<AxisMask> none;
  const std::vector<AxisMask>& held = conditions ? conditions->heldAxes() : none;
  if (const std::string problem = staticHoldProblem(positions, masses, held); !problem.empty())
  {
    throw InvalidInputError(problem);
  }
  BodyElements undamped = elements;
  Network = *elements.network;
  std::fill(Network.springDamping.begin(), Network.springDamping.end(), 0.0);
  std::fill(Network.volumeDamping.begin(), Network.volumeDamping.end(), 0.0);
  undamped.network = &Network;
  if (elements.tets)
  {
    Tets = *elements.tets;
    Tets.damped = false;
    undamped.tets = &Tets;
  }
  Newton = std::make_unique<ImplicitEulerStepper>(topology, undamped, masses, restPositions, scene, true);
}

void StaticStepper::step(double h, DynamicState& state, StepPlan& plan)
{
  std::fill(state.velocities.begin(), state.velocities.end(), Vec3::Zero());
  Newton->step(h, state, plan);
  std::fill(state.velocities.begin(), state.velocities.end(), Vec3::Zero());
}

} // namespace softbody

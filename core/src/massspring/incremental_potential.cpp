#include "softbody/massspring/incremental_potential.h"

#include "softbody/common/parallel.h"

#include <algorithm>
#include <cmath>

namespace softbody
{

IncrementalPotential::IncrementalPotential(
  std::size_t vertexCount, const PointMasses& masses, const Vec3& gravity)
  : InverseMass(masses.inverseMass)
  , Gravity(gravity)
{
  Active.resize(vertexCount);
  for (std::size_t i = 0; i < vertexCount; ++i)
  {
    Active[i] = InverseMass[i] > 0.0 ? 1 : 0;
    ActiveMass += Active[i] ? 1.0 / InverseMass[i] : 0.0;
  }
}

void IncrementalPotential::beginStep(
  const std::vector<Vec3>& x0, const std::vector<Vec3>& v0, double h, double t0)
{
  H = h;
  EndTime = t0 + h;
  X0 = x0;
  const double momentum = parallelSum(x0.size(), [&](std::size_t i) {
    return Active[i] ? v0[i].squaredNorm() / InverseMass[i] : 0.0;
  });
  SpeedScale = ActiveMass > 0.0 ? std::sqrt(momentum / ActiveMass) : 0.0;
  Target.resize(x0.size());
  parallelFor(x0.size(), 4096, [&](std::size_t i) {
    Target[i] = Active[i] ? Vec3(x0[i] + h * v0[i]) : x0[i];
  });
  LoadScale = 0.0;
  if (Conditions)
  {
    Conditions->holdPositions(EndTime, Target);
    if (Conditions->hasLoads())
    {
      Conditions->deadLoads(EndTime, x0, DeadLoad);
      PullForce.assign(x0.size(), Vec3::Zero());
      Conditions->addPullForces(EndTime, x0, PullForce);
      const double load = parallelSum(x0.size(), [&](std::size_t i) {
        return Active[i] ? (DeadLoad[i] + PullForce[i]).squaredNorm() * InverseMass[i] : 0.0;
      });
      LoadScale = ActiveMass > 0.0 ? std::sqrt(load / ActiveMass) : 0.0;
    }
  }
  beginElements();
}

double IncrementalPotential::addLoadTerms(const std::vector<Vec3>& x, std::vector<Vec3>& gradient)
{
  double contact = 0.0;
  if (ContactLoad)
  {
    const std::vector<Vec3>& load = *ContactLoad;
    parallelFor(x.size(), kVertexGrain, [&](std::size_t i) {
      if (Active[i])
      {
        gradient[i] -= load[i];
      }
    });
    contact = -parallelSum(x.size(), [&](std::size_t i) {
      return Active[i] ? load[i].dot(x[i] - X0[i]) : 0.0;
    });
  }
  if (!Conditions || !Conditions->hasLoads())
  {
    return contact;
  }
  PullForce.assign(x.size(), Vec3::Zero());
  const double pull = Conditions->hasPull() ? Conditions->addPullForces(EndTime, x, PullForce) : 0.0;
  parallelFor(x.size(), kVertexGrain, [&](std::size_t i) {
    if (Active[i])
    {
      gradient[i] -= DeadLoad[i] + PullForce[i];
    }
  });
  // The dead load's work from x0, like gravity's: the same minimizer, small values.
  return contact + pull - parallelSum(x.size(), [&](std::size_t i) {
    return Active[i] ? DeadLoad[i].dot(x[i] - X0[i]) : 0.0;
  });
}

void IncrementalPotential::addLoadHessian(BlockSparseMatrix& hessian)
{
  if (!Conditions || !Conditions->hasPull())
  {
    return;
  }
  Conditions->pullStiffness(EndTime, PullStiffness);
  for (std::size_t i = 0; i < Active.size(); ++i)
  {
    if (Active[i] && PullStiffness[i] > 0.0)
    {
      hessian.block(hessian.diagonalSlot(i)) += PullStiffness[i] * Mat3::Identity();
    }
  }
}

void IncrementalPotential::beginVertexBlocks()
{
  PullStiffness.assign(Active.size(), 0.0);
  if (Conditions && Conditions->hasPull())
  {
    Conditions->pullStiffness(EndTime, PullStiffness);
  }
}

void IncrementalPotential::vertexBlock(std::size_t i, const std::vector<Vec3>& y, const std::vector<Vec3>& evaluated,
  Vec3& gradient, Mat3& hessian) const
{
  const double m = 1.0 / InverseMass[i];
  if (Static)
  {
    gradient = -m * Gravity;
    hessian.setZero();
  }
  else
  {
    const double h2 = H * H;
    gradient = m * ((y[i] - Target[i]) / h2 - Gravity);
    hessian = (m / h2) * Mat3::Identity();
  }
  if (Conditions && Conditions->hasLoads())
  {
    const double k = PullStiffness.empty() ? 0.0 : PullStiffness[i];
    gradient -= DeadLoad[i] + PullForce[i] - k * (y[i] - evaluated[i]);
    hessian += k * Mat3::Identity();
  }
  if (ContactLoad)
  {
    gradient -= (*ContactLoad)[i];
  }
  addElementBlock(i, y, gradient, hessian);
}

void IncrementalPotential::predict(std::vector<Vec3>& x, bool withGravity) const
{
  const Vec3 drift = withGravity ? Vec3(H * H * Gravity) : Vec3::Zero();
  x.resize(Target.size());
  parallelFor(Target.size(), 4096, [&](std::size_t i) { x[i] = Active[i] ? Vec3(Target[i] + drift) : Target[i]; });
  if (Conditions && !Conditions->heldAxes().empty())
  {
    Conditions->holdPositions(EndTime, x);
  }
}

double IncrementalPotential::inertialEnergy(const std::vector<Vec3>& x) const
{
  const double h2 = H * H;
  return parallelSum(x.size(), [&](std::size_t i) {
    if (!Active[i])
    {
      return 0.0;
    }
    const double m = 1.0 / InverseMass[i];
    // Gravity's work from x0 rather than from the origin: the same minimizer, and Phi stays
    // small enough that its rounding does not hide the last iterations' progress.
    const double work = m * Gravity.dot(x[i] - X0[i]);
    return Static ? -work : 0.5 * m * (x[i] - Target[i]).squaredNorm() / h2 - work;
  });
}

double IncrementalPotential::referenceAcceleration(double gravityNorm) const
{
  return std::max({ gravityNorm, SpeedScale / H, LoadScale, 1e-12 });
}

double IncrementalPotential::residualAcceleration(const std::vector<Vec3>& gradient) const
{
  if (!(ActiveMass > 0.0))
  {
    return 0.0;
  }
  const double sum = parallelSum(gradient.size(), [&](std::size_t i) {
    return Active[i] ? gradient[i].squaredNorm() * InverseMass[i] : 0.0;
  });
  return std::sqrt(sum / ActiveMass);
}

} // namespace softbody

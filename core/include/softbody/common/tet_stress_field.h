// What a stepper reports of its tets' strain and stress (continuum models, tet_elastic_forces.h):
// one entry per tet, symmetric tensors in VTK's component order.
#pragma once

#include <array>
#include <vector>

namespace softbody
{

/// A symmetric tensor in VTK's order XX, YY, ZZ, XY, YZ, XZ.
using SymmetricTensor = std::array<double, 6>;

/// Per tet, at the current positions.
struct TetStressField
{
  std::vector<SymmetricTensor> greenStrain;  ///< E = (F^T F - I) / 2
  std::vector<SymmetricTensor> cauchyStress; ///< sigma = P F^T / J [Pa]; NaN for J <= 0
  std::vector<double> vonMises;              ///< sqrt(3/2 s : s), s = dev(sigma) [Pa]
  std::vector<double> energyDensity;         ///< Psi(F) per rest volume [J/m^3]
  bool empty() const { return energyDensity.empty(); }
};

} // namespace softbody

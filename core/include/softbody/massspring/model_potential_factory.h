// The one place that names each material model for the implicit integrators: it builds the
// incremental potential (incremental_potential.h) of the body's model, so Implicit Euler and
// Projective Dynamics hold an IncrementalPotential and never name a model. A new model adds its
// line here (and its entry in the material settings it is chosen by).
#pragma once

#include "softbody/massspring/incremental_potential.h"

#include <memory>

namespace softbody
{

/// The potential of the spring network over `constants` (the only model so far).
std::unique_ptr<IncrementalPotential> makeIncrementalPotential(const Topology& topology,
  const ElementConstants& constants, const PointMasses& masses, const Vec3& gravity);

} // namespace softbody

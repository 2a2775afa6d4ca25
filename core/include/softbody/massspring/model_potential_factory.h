// The one place that names each material model for the implicit integrators: it builds the
// incremental potential (incremental_potential.h) of the body's model, so Implicit Euler, the
// static solve and Projective Dynamics hold an IncrementalPotential and never name a model. A
// new model adds its line here (and its entry in the material settings it is chosen by).
#pragma once

#include "softbody/massspring/incremental_potential.h"
#include "softbody/material/tet_elasticity.h"

#include <memory>

namespace softbody
{

/// A body's elements as the implicit integrators see them: its model and its constants.
struct BodyElements
{
  MaterialModel model = MaterialModel::SpringNetwork;
  const ElementConstants* network = nullptr; ///< always given (the spring network's)
  const TetElasticConstants* tets = nullptr; ///< given for the continuum models
};

/// The potential of the body's model.
std::unique_ptr<IncrementalPotential> makeIncrementalPotential(const Topology& topology,
  const BodyElements& elements, const PointMasses& masses, const Vec3& gravity);

} // namespace softbody

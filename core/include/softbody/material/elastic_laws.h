// The one place that maps a continuum MaterialModel to its law (isotropic_elasticity.h). Every
// consumer (the implicit integrators' potential, the explicit forces, XPBD's constraints, the rest
// data, the model's name) goes through withElasticLaw, so a new law is its struct, its XPBD form
// (constraint_forms.h), its MaterialModel value and one case here.
#pragma once

#include "softbody/material/isotropic_elasticity.h"
#include "softbody/material/material.h"

namespace softbody
{

/// f(Law{}) with the law of a continuum model, chosen once (not per element).
template <class Function>
decltype(auto) withElasticLaw(MaterialModel model, Function&& function)
{
  switch (model)
  {
    case MaterialModel::StableNeoHookean:
      return function(StableNeoHookeanLaw{});
    default:
      return function(CorotatedLaw{});
  }
}

} // namespace softbody

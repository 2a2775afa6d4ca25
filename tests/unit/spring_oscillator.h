// The linear oscillator the integrator tests share: point 1 of mass m on an undamped spring to
// pinned point 0 along x, without gravity, started at rest stretched by A, so that
// x(t) = L + A cos(w t), w = sqrt(k / m). Newton solves it to 1e-12.
#pragma once

#include "softbody/massspring/mass_spring_settings.h"
#include "softbody/massspring/model_potential_factory.h" // BodyElements
#include "softbody/material/mass.h"
#include "softbody/material/spring_network.h"
#include "softbody/mesh/topology.h"

#include <cmath>

namespace softbody::test
{

struct SpringOscillator
{
  double k = 400.0, m = 0.25, l0 = 0.1, amplitude = 0.02;
  Topology topology;
  ElementConstants constants;
  PointMasses masses;
  SceneSettings scene;
  std::vector<Vec3> restPositions;

  SpringOscillator()
  {
    topology.vertexCount = 2;
    topology.edges = { Edge{ 0, 1 } };
    topology.vertexEdges = buildCsr(2, { 0, 1 }, { 0, 0 });
    topology.vertexTetCorners = buildCsr(2, {}, {});
    constants.restLength = { l0 };
    constants.springStiffness = { k };
    constants.springDamping = { 0.0 };
    masses.mass = { 1.0, m };
    masses.inverseMass = { 0.0, 1.0 / m };
    masses.totalMass = 1.0 + m;
    restPositions = { Vec3::Zero(), Vec3(l0, 0, 0) };
    scene.gravity = Vec3::Zero();
    scene.implicit.tolerance = 1e-12;
    scene.implicit.maxIterations = 50;
  }
  double omega() const { return std::sqrt(k / m); }
  double exact(double t) const { return l0 + amplitude * std::cos(omega() * t); }
  BodyElements elements() const { return { MaterialModel::SpringNetwork, &constants, nullptr }; }
};

} // namespace softbody::test

// What the GPU stepper's tests share: making a GPU simulation or skipping where no context
// exists, and the tolerances of GPU against CPU.
#pragma once

#include "softbody/gpu/mass_spring_gpu_simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>

namespace softbody::test
{

/// Largest |x_gpu - x_cpu| over the body's size while the motion is smooth (free fall, before
/// any threshold-triggered stage acts), after the GPU path has taken its steps in double
/// precision too. Measured: 0 (bitwise equal) on Mesa llvmpipe, 1e-16 on an NVIDIA H200.
constexpr double kGpuRelativeTolerance = 1e-9;

/// Bounds once the stages that act on a threshold have acted (the strain limiter past its
/// limit, floor contact, static friction's stick-or-slide). Mesa's llvmpipe rounds every
/// double operation as the CPU does and stays bitwise equal (measured), so the tight bound
/// holds there. A hardware GPU fuses multiply-adds and rounds sqrt and division its own way: a
/// 1-ulp difference then decides differently for a point right at a threshold, and that
/// different decision (a limiter correction, a contact) is what separates the runs. Measured
/// on an NVIDIA H200 after 532-579 steps, frictionless: up to 4.4e-5 of the size and
/// 0.021 m/s. A wrong kernel is off by far more (a dropped term moves the body by millimetres
/// within a few steps: tests/mutation).
struct GpuTolerance
{
  double position; ///< of the body's size
  double velocity; ///< m/s
};

inline bool softwareRenderer(const gpu::MassSpringGpuSimulation& gpu)
{
  const std::string& renderer = gpu.glRenderer();
  return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
}

inline GpuTolerance afterThresholdStages(const gpu::MassSpringGpuSimulation& gpu)
{
  return softwareRenderer(gpu) ? GpuTolerance{ kGpuRelativeTolerance, 1e-9 } : GpuTolerance{ 2e-4, 0.1 };
}

/// The GPU stepper, or null (and the test skips) where no context can be made. Any other
/// failure (a kernel that does not compile, say) fails the test: it is a bug, not a machine
/// without a GPU.
inline std::unique_ptr<gpu::MassSpringGpuSimulation> makeGpu(
  const Body& body, const SceneSettings& scene)
{
  std::string whyNot;
  auto simulation = gpu::tryCreateGpuMassSpring(body, scene, whyNot);
  if (!simulation)
  {
    std::cerr << "GPU unavailable: " << whyNot << "\n";
    const bool noContext = whyNot.rfind("No OpenGL", 0) == 0;
    EXPECT_TRUE(noContext) << "the GPU stepper failed for another reason than a missing context";
  }
  return simulation;
}

/// A material model and an explicit integrator, the parameter of the GPU parity suites.
using ModelAndIntegrator = std::tuple<MaterialModel, Integrator>;

/// GoogleTest's name for it: "StableNeoHookean_EulerCromer" (letters and digits only).
inline std::string modelAndIntegratorName(const ::testing::TestParamInfo<ModelAndIntegrator>& param)
{
  std::string name = std::string(materialModelName(std::get<0>(param.param))) + "_" +
    integratorName(std::get<1>(param.param));
  name.erase(std::remove_if(name.begin(), name.end(), [](char c) { return c == '-' || c == ' '; }), name.end());
  return name;
}

} // namespace softbody::test

#define MAKE_GPU_OR_SKIP(name, body, scene)                                                       \
  auto name = ::softbody::test::makeGpu(body, scene);                                             \
  if (!name)                                                                                      \
  {                                                                                               \
    GTEST_SKIP() << "no EGL / OpenGL 4.3 context here";                                          \
  }

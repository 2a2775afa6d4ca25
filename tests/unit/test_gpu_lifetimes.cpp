// GPU simulations created and destroyed in every order a ParaView session produces, then a
// normal process exit (what can go wrong: eight Soft Body filters, four of them on the GPU,
// crashing in free() at teardown and the process never exiting).
//
// A plain program rather than a GoogleTest case, because what it checks is the exit itself:
// it returns from main() with simulations still alive in static storage (destroyed by the C++
// runtime during exit(), after main's locals, as a filter owned by a ParaView singleton would
// be) and CTest sees the exit status. Exit code 77 (skipped) where no EGL / OpenGL 4.3 context
// can be made.
#include "softbody/gpu/mass_spring_gpu_simulation.h"
#include "softbody/massspring/mass_spring_simulation.h"
#include "softbody/mesh/mesh_generators.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using namespace softbody;

namespace
{

constexpr int kSkip = 77;

const Integrator kIntegrators[] = { Integrator::Euler, Integrator::Midpoint, Integrator::Verlet,
  Integrator::EulerCromer };

int failures = 0;

void check(bool condition, const std::string& what)
{
  std::cout << (condition ? "ok    " : "FAIL  ") << what << std::endl;
  if (!condition)
  {
    ++failures;
  }
}

Body box(int n)
{
  Body body;
  body.mesh = makeTetBox(n, n, n, 0.02, Vec3(0.0, 0.0, 0.01));
  return body;
}

SceneSettings scene(Integrator integrator)
{
  SceneSettings s;
  s.integrator = integrator;
  s.floorEnabled = true;
  return s;
}

std::unique_ptr<gpu::MassSpringGpuSimulation> makeGpu(Integrator integrator, int n = 4)
{
  std::string whyNot;
  auto simulation = gpu::tryCreateGpuMassSpring(box(n), scene(integrator), whyNot);
  if (!simulation)
  {
    if (whyNot.rfind("No OpenGL", 0) == 0)
    {
      std::cout << "SKIP: no EGL / OpenGL 4.3 context here: " << whyNot << std::endl;
      std::exit(kSkip);
    }
    std::cerr << "the GPU stepper failed for another reason than a missing context: " << whyNot
              << std::endl;
    std::exit(1);
  }
  return simulation;
}

/// Steps `simulation` by `steps` of its own step and checks it against the CPU stepper.
bool matchesCpu(gpu::MassSpringGpuSimulation& simulation, Integrator integrator, int n, int steps)
{
  MassSpringSimulation cpu(box(n), scene(integrator));
  const double end = simulation.state().time + steps * simulation.stepSize();
  simulation.advance(end);
  cpu.advance(end);
  const std::vector<Vec3>& a = simulation.state().positions;
  const std::vector<Vec3>& b = cpu.state().positions;
  double difference = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    difference = std::max(difference, (a[i] - b[i]).cwiseAbs().maxCoeff());
  }
  return a.size() == b.size() && difference <= 1e-9;
}

// Destroyed by exit(), after main() returned: the order in which a ParaView session's last
// filters may go (process-module singletons, Python finalization).
std::vector<std::unique_ptr<gpu::MassSpringGpuSimulation>> survivors;

} // namespace

int main()
{
  // 1. Several alive at once, one per integrator, stepped in turns, destroyed in another order.
  {
    std::vector<std::unique_ptr<gpu::MassSpringGpuSimulation>> alive;
    for (Integrator integrator : kIntegrators)
    {
      alive.push_back(makeGpu(integrator));
    }
    bool allMatch = true;
    for (int round = 0; round < 2; ++round)
    {
      for (std::size_t i = 0; i < alive.size(); ++i)
      {
        allMatch = matchesCpu(*alive[i], kIntegrators[i], 4, 20) && allMatch;
      }
    }
    check(allMatch, "four simulations alive at once, stepped in turns, match the CPU");
    alive.erase(alive.begin() + 1); // from the middle
    alive.erase(alive.begin());     // the oldest
    alive.pop_back();               // the newest
    alive.clear();
    check(true, "destroyed in mixed order");
  }

  // 2. Interleaved: create one, destroy an older one, create another, ...
  {
    std::vector<std::unique_ptr<gpu::MassSpringGpuSimulation>> window;
    bool allMatch = true;
    for (int i = 0; i < 16; ++i)
    {
      const Integrator integrator = kIntegrators[i % 4];
      window.push_back(makeGpu(integrator, 3 + i % 3));
      allMatch = matchesCpu(*window.back(), integrator, 3 + i % 3, 5) && allMatch;
      if (window.size() > 3)
      {
        window.erase(window.begin() + (i % 3));
      }
    }
    check(allMatch, "sixteen simulations created and destroyed interleaved match the CPU");
  }

  // 3. Created, stepped and destroyed from several caller threads at the same time (pvbatch
  //    or a threaded caller): each caller owns its simulations.
  {
    std::vector<int> results(4, 0);
    std::vector<std::thread> callers;
    for (int t = 0; t < 4; ++t)
    {
      callers.emplace_back([t, &results] {
        bool ok = true;
        for (int round = 0; round < 3; ++round)
        {
          auto a = makeGpu(kIntegrators[t], 3);
          auto b = makeGpu(kIntegrators[(t + 1) % 4], 3);
          ok = matchesCpu(*a, kIntegrators[t], 3, 5) && ok;
          ok = matchesCpu(*b, kIntegrators[(t + 1) % 4], 3, 5) && ok;
        }
        results[static_cast<std::size_t>(t)] = ok ? 1 : 0;
      });
    }
    for (std::thread& caller : callers)
    {
      caller.join();
    }
    bool allOk = true;
    for (int r : results)
    {
      allOk = allOk && r == 1;
    }
    check(allOk, "simulations on four caller threads at once match the CPU");
  }

  // 4. Some left alive for exit(): one created by a thread that has ended since, and the
  //    four integrators with state on the GPU.
  std::thread([] { survivors.push_back(makeGpu(Integrator::Verlet)); }).join();
  for (Integrator integrator : kIntegrators)
  {
    survivors.push_back(makeGpu(integrator));
    survivors.back()->advance(10 * survivors.back()->stepSize());
  }
  check(survivors.size() == 5, "five simulations left alive for the process exit");

  std::cout << (failures == 0 ? "all checks passed; exiting with simulations alive"
                              : "some checks failed")
            << std::endl;
  return failures == 0 ? 0 : 1;
}

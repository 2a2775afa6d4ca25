/**
 * @brief   The Soft Body filter's initial state: a velocity (uniform, a spin about the centre of
 *          mass, a point array) and a start from a deformed state (rest + a displacement array).
 *
 * Applied to a freshly built simulation before its frame 0 is cached. Points that do not move
 * (inverse mass 0: pinned, or held by a condition) keep the state their stepper gave them.
 */
#ifndef vtkSoftBodyInitialState_h
#define vtkSoftBodyInitialState_h

#include "vtkSoftBodySettings.h"

#include <string>

class vtkUnstructuredGrid;
namespace softbody
{
class Simulation;
}

namespace vtkSoftBodyInitialState
{
/// Sets the initial positions and velocities of `simulation` (built from `input`); a message
/// naming the array and what is wrong with it, empty on success (nothing changed then).
std::string Apply(vtkUnstructuredGrid* input, const vtkSoftBodyCoreSettings::InitialState& initial,
  softbody::Simulation& simulation);
}

#endif

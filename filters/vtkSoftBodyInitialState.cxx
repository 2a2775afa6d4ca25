#include "vtkSoftBodyInitialState.h"

#include "softbody/common/simulation.h"

#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <sstream>

namespace
{

/// The point array `name` of `input` as vectors, or a message for the user.
std::string VectorArray(vtkUnstructuredGrid* input, const std::string& property,
  const std::string& name, std::vector<softbody::Vec3>& values)
{
  vtkDataArray* array = input->GetPointData()->GetArray(name.c_str());
  if (!array || array->GetNumberOfComponents() != 3)
  {
    std::ostringstream s;
    s << property << " '" << name << "' is not a 3-component numeric point array of the input. Its point arrays:";
    for (int i = 0; i < input->GetPointData()->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* a = input->GetPointData()->GetArray(i);
      if (a && a->GetName())
      {
        s << " '" << a->GetName() << "' (" << a->GetNumberOfComponents() << " components)";
      }
    }
    s << ".";
    return s.str();
  }
  values.resize(static_cast<std::size_t>(array->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    const double* v = array->GetTuple3(i);
    values[static_cast<std::size_t>(i)] = softbody::Vec3(v[0], v[1], v[2]);
    if (!values[static_cast<std::size_t>(i)].allFinite())
    {
      std::ostringstream s;
      s << property << " '" << name << "' has a non-finite value at point " << i << ".";
      return s.str();
    }
  }
  return {};
}

} // namespace

//------------------------------------------------------------------------------
std::string vtkSoftBodyInitialState::Apply(vtkUnstructuredGrid* input,
  const vtkSoftBodyCoreSettings::InitialState& initial, softbody::Simulation& simulation)
{
  const bool moves = initial.velocity != softbody::Vec3::Zero() || initial.spin != softbody::Vec3::Zero();
  if (!moves && initial.velocityArray.empty() && initial.displacementArray.empty())
  {
    return {};
  }
  softbody::DynamicState state = simulation.state();
  const std::vector<double>& w = simulation.inverseMasses();
  const std::size_t n = state.positions.size();
  if (static_cast<std::size_t>(input->GetNumberOfPoints()) != n)
  {
    return "The initial state needs one simulated point per input point, but the input has " +
      std::to_string(input->GetNumberOfPoints()) + " points and the body " + std::to_string(n) + ".";
  }
  std::vector<softbody::Vec3> displacement, velocity;
  if (!initial.displacementArray.empty())
  {
    const std::string error =
      VectorArray(input, "InitialDisplacementArray", initial.displacementArray, displacement);
    if (!error.empty())
    {
      return error;
    }
  }
  if (!initial.velocityArray.empty())
  {
    const std::string error = VectorArray(input, "InitialVelocityArray", initial.velocityArray, velocity);
    if (!error.empty())
    {
      return error;
    }
  }
  for (std::size_t i = 0; i < n && !displacement.empty(); ++i)
  {
    if (w[i] > 0.0)
    {
      state.positions[i] = simulation.restPositions()[i] + displacement[i];
    }
  }
  // The spin turns the (displaced) body about its centre of mass.
  softbody::Vec3 centre = softbody::Vec3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (w[i] > 0.0)
    {
      centre += state.positions[i] / w[i];
      mass += 1.0 / w[i];
    }
  }
  centre = mass > 0.0 ? softbody::Vec3(centre / mass) : centre;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (w[i] > 0.0)
    {
      state.velocities[i] = initial.velocity + initial.spin.cross(state.positions[i] - centre) +
        (velocity.empty() ? softbody::Vec3::Zero() : velocity[i]);
    }
  }
  simulation.restoreState(state);
  return {};
}

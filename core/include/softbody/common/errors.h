// Exceptions thrown by softbody_core. The filters turn them into vtkErrorMacro messages.
#pragma once

#include <stdexcept>
#include <string>

namespace softbody
{

/// The body or the settings cannot be simulated (bad mesh, out-of-range parameter).
/// The message is written for the end user: it says what is wrong and what to do.
class InvalidInputError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// The state became non-finite or exploded; the message names the simulated time.
class SimulationDivergedError : public std::runtime_error
{
public:
  SimulationDivergedError(const std::string& message, double simulatedTime)
    : std::runtime_error(message)
    , time(simulatedTime)
  {
  }
  double time; ///< simulated time [s] at which the divergence was detected
};

} // namespace softbody

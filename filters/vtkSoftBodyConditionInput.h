/**
 * @class   vtkSoftBodyConditionInput
 * @brief   The Soft Body filter's Conditions input (port 3) as core conditions on its body.
 *
 * Each connection is the output of a Soft Body Condition: its field data describes the
 * condition (vtkSoftBodyConditionCodec), its points are the set. The set is found among the
 * body's points by position (within a billionth of the body's size; coincident body points are
 * all taken), so it does not depend on point numbers: a condition made on the source of the
 * body, on a filter that keeps its points, or under MPI on another rank's piece (the sets are
 * gathered from every rank first) selects the same points. A set point that is not a point of
 * the body is refused, except under MPI, where it belongs to another rank's bodies.
 *
 * The conversion is kept while the body and the connections are unchanged (the same objects at
 * the same modification times), so requests for other times cost no search.
 */
#ifndef vtkSoftBodyConditionInput_h
#define vtkSoftBodyConditionInput_h

#include "softbody/scene/conditions.h"

#include "vtkType.h"

#include <string>
#include <utility>
#include <vector>

class vtkInformationVector;
class vtkUnstructuredGrid;

class vtkSoftBodyConditionInput
{
public:
  /// The conditions connected to `port` with their sets in `body`'s point numbers; a message
  /// for the user when a connection is not a condition or names points the body lacks.
  std::string Read(vtkInformationVector* port, vtkUnstructuredGrid* body,
    std::vector<softbody::Condition>& conditions);

  /// What the last conversion has to say (under MPI: a total force or pull whose set spans
  /// bodies on several ranks), to be warned once.
  const std::vector<std::string>& GetWarnings() const { return this->Warnings; }

private:
  std::vector<std::string> Warnings;
  using Key = std::vector<std::pair<const void*, vtkMTimeType>>;
  Key Converted; ///< body, then each connection, as last converted
  std::vector<softbody::Condition> Conditions;
};

#endif

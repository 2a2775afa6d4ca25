/**
 * @class   vtkSoftBodyConditionOutput
 * @brief   What the Conditions do, on the Soft Body Mesh output: the supports' reactions.
 *
 * Point array Reaction [N]: the force the held components of each point need from its support
 * (zero on free components and free points), present when some condition holds points. Field
 * data, per condition, "<name> Force" [N] and "<name> Moment" [N m] about the set's current
 * centroid: for Fixed and Prescribed Motion the supports' total reaction, for the loads the
 * force they apply; Plot Data Over Time plots them against time.
 */
#ifndef vtkSoftBodyConditionOutput_h
#define vtkSoftBodyConditionOutput_h

#include "softbody/scene/boundary_conditions.h"

class vtkUnstructuredGrid;

struct vtkSoftBodyConditionOutput
{
  /// Adds the arrays of `readout` (reactions in the output's point order) to `output`.
  static void Add(const softbody::ConditionReadout& readout, vtkUnstructuredGrid* output);
};

#endif

/**
 * @class   vtkSoftBodyPbdAdapter
 * @brief   The PBD/XPBD side of vtkSoftBodyFilter: the body from the input, and the outputs
 *          only position-based methods have.
 *
 * Kept apart from the filter so the filter stays a dispatcher between methods.
 */
#ifndef vtkSoftBodyPbdAdapter_h
#define vtkSoftBodyPbdAdapter_h

#include "softbody/pbd/pbd_reordered.h"
#include "softbody/pbd/pbd_simulation.h"

#include "vtkType.h"

#include <memory>
#include <string>
#include <vector>

struct vtkSoftBodyCoreSettings;
class vtkTable;
class vtkUnstructuredGrid;

class vtkSoftBodyPbdAdapter
{
public:
  /// Converts the input and builds the simulation (particles renumbered for locality, outputs
  /// in the input's order) and sets `solver` to the PbdSimulation inside it. Returns null and
  /// sets `error` for input the filter must refuse; throws softbody::InvalidInputError for what
  /// core refuses.
  std::unique_ptr<softbody::Simulation> Create(const vtkSoftBodyCoreSettings& settings,
    vtkUnstructuredGrid* input, std::string& error, softbody::PbdSimulation*& solver);

  /// Cell array "Broken" (a broken link, or a tet with a broken edge) and, where any cell is
  /// broken, vtkGhostType with HIDDENCELL on those cells so renderings show the fragments apart.
  void AddBrokenCells(const softbody::PbdSimulation& simulation, vtkUnstructuredGrid* output) const;

  /// Spreads per-tet values (core's tet order) over the input cells; NaN for cells that are not
  /// tets.
  std::vector<double> PerInputCell(const std::vector<double>& perTet, vtkIdType numCells) const;

  /// Field data "Iterations" and "Residual" of the last step.
  static void AddConvergenceFields(const softbody::PbdSimulation& simulation, vtkUnstructuredGrid* output);

  /// Columns "Iteration" and "Residual": the residual after each iteration of the last step.
  static void FillConvergenceTable(const softbody::PbdSimulation& simulation, vtkTable* output);

private:
  std::vector<vtkIdType> TetCells;  ///< input cell of each core tet
  std::vector<vtkIdType> LinkCells; ///< input cell of each explicit link
};

#endif

/**
 * @class   vtkSoftBodyMethodChoice
 * @brief   Method Automatic, the Soft Body filter's default: the method the input's cells need.
 *
 * A tet mesh goes to Mass-Spring (the tet model, every integrator and material model); a body
 * of linked particles, as Soft Body Voxelize and Soft Body Cloth make (line cells, with or
 * without tets or quads), goes to XPBD, which simulates links, where Mass-Spring would refuse
 * them. So the project's own filters feed Soft Body at its defaults.
 *
 * Under MPI the ranks hold pieces (some may be empty): the cells present are reduced over the
 * ranks, so every rank picks the method the serial run picks. Collective: every rank calls it.
 */
#ifndef vtkSoftBodyMethodChoice_h
#define vtkSoftBodyMethodChoice_h

#include <string>

class vtkDataSet;
class vtkMultiProcessController;

class vtkSoftBodyMethodChoice
{
public:
  /// The method to run: `method` itself unless it is METHOD_AUTOMATIC, then MASS_SPRING or XPBD
  /// from the cells of `input` (this rank's piece; null: none) over every rank of `controller`.
  /// `note` gets what Automatic chose and why when it chose XPBD (else it is emptied).
  static int Resolve(int method, vtkDataSet* input, vtkMultiProcessController* controller,
    std::string& note);

  /// "Mass-Spring", "PBD" or "XPBD": the name the Method property shows.
  static const char* Name(int method);
};

#endif

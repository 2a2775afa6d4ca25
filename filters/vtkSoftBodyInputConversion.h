/**
 * @class   vtkSoftBodyInputConversion
 * @brief   Checks a VTK tetrahedral grid and converts it, once, into core's TetMesh.
 *
 * The checks here are the ones only VTK can make (cell types, the pinned-points array). The
 * geometric checks (non-finite coordinates, bad or degenerate tets, inverted tets) belong to
 * softbody::prepareTetMesh, which the simulation runs on what this class produces, so that the
 * filter and the core library report them with the same words.
 *
 * The input is only read: points are copied to double precision (the input may hold floats),
 * tets are listed in input cell order so per-tet results map back to input cells one to one.
 */
#ifndef vtkSoftBodyInputConversion_h
#define vtkSoftBodyInputConversion_h

#include "softbody/massspring/mass_spring_simulation.h" // softbody::Body
#include "softbody/pbd/pbd_simulation.h"          // softbody::Body

#include "vtkType.h" // vtkIdType

#include <string>

class vtkUnstructuredGrid;

class vtkSoftBodyInputConversion
{
public:
  /**
   * Fills `body.mesh` (points and tets) and `body.pinned` from `input`. `pinnedArrayName` names
   * a point-data array whose nonzero values (in any component) mark pinned points; empty or
   * "None" means no pinned points. Returns an empty string on success, otherwise the message
   * to show the user (`body` is then unspecified).
   */
  static std::string Convert(
    vtkUnstructuredGrid* input, const std::string& pinnedArrayName, softbody::Body& body);

  /**
   * For PBD and XPBD: tetrahedra (volumes and edges), line and poly-line cells (a distance link
   * per segment, scaled by the cell array "LinkStiffnessScale" when present), and any vertex
   * or surface cells, which add nothing and move with their points. A point array "Mass" [kg]
   * gives the masses. `tetCells[k]` and `linkCells[j]` are the input cells of tet k and
   * explicit link j. Returns an empty string on success, otherwise the message for the user.
   */
  static std::string ConvertParticles(vtkUnstructuredGrid* input,
    const std::string& pinnedArrayName, softbody::Body& body, std::vector<vtkIdType>& tetCells,
    std::vector<vtkIdType>& linkCells);

  /**
   * The per-cell material values of the named cell arrays (empty names: uniform) into `cells`,
   * one per input cell (which are all tets for Mass-Spring). Returns the message for the user
   * when an array is missing, not numeric or has more than one component; the values
   * themselves are core's to check (each refusal names the cell).
   */
  static std::string ConvertCellMaterial(vtkUnstructuredGrid* input,
    const std::string& youngsModulusArray, const std::string& poissonRatioArray,
    const std::string& densityArray, softbody::CellMaterial& cells);

  /// True when `name` selects no array (empty or the XML domain's "None" entry).
  static bool IsNoArray(const std::string& name);

private:
  static std::string CheckSize(vtkUnstructuredGrid* input);
  static std::string ConvertPoints(vtkUnstructuredGrid* input, softbody::TetMesh& mesh);
  static std::string ConvertTets(vtkUnstructuredGrid* input, softbody::TetMesh& mesh);
  static std::string ConvertPinned(
    vtkUnstructuredGrid* input, const std::string& pinnedArrayName, std::vector<char>& pinned);
};

#endif

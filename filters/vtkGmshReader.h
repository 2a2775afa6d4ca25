/**
 * @class   vtkGmshReader
 * @brief   Reads the nodes and tetrahedra of a Gmsh .msh file (ASCII format 2.2 or 4.1).
 *
 * Output: a vtkUnstructuredGrid of VTK_TETRA cells in file order, corners as stored (a file's
 * inverted tets stay inverted, so that a quality check can report them). Linear hexahedra,
 * prisms and pyramids are split into 6, 3 and 2 tets (conforming), with a vtkWarningMacro per
 * type counting them; higher-order volume cells are refused. Field data "SkippedElements"
 * counts the elements that are not volume cells. Missing, truncated or garbled files end in
 * vtkErrorMacro with the file and line (excerpts escaped and shortened), and an empty output;
 * never a crash.
 *
 * The parsing is softbody::readGmshMesh (core library); this class only adapts it to VTK.
 */
#ifndef vtkGmshReader_h
#define vtkGmshReader_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <string> // for std::string

class SOFTBODYFILTERS_EXPORT vtkGmshReader : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkGmshReader* New();
  vtkTypeMacro(vtkGmshReader, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The file to read: the .msh file (ASCII 2.2 or 4.1; binary files are refused).
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkGmshReader();
  ~vtkGmshReader() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  std::string FileName;

private:
  vtkGmshReader(const vtkGmshReader&) = delete;
  void operator=(const vtkGmshReader&) = delete;
};

#endif

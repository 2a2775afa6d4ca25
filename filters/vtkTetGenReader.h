/**
 * @class   vtkTetGenReader
 * @brief   Reads a tetrahedral mesh from TetGen .node/.ele files (TetGen's own loader).
 *
 * Output: a vtkUnstructuredGrid of VTK_TETRA cells in file order, corners as stored (a file's
 * inverted tets stay inverted, so that a quality check can report them). Field data
 * "SkippedElements" counts elements that are not 4-node tets. Missing, truncated or garbled
 * files end in vtkErrorMacro with the file and line, and an empty output; never a crash.
 *
 * The parsing is softbody::readTetGenMesh (core library); this class only adapts it to VTK.
 */
#ifndef vtkTetGenReader_h
#define vtkTetGenReader_h

#include "SoftBodyFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

#include <string> // for std::string

class SOFTBODYFILTERS_EXPORT vtkTetGenReader : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkTetGenReader* New();
  vtkTypeMacro(vtkTetGenReader, vtkUnstructuredGridAlgorithm)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The file to read: the .node or the .ele file (both must exist side by side).
   */
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

protected:
  vtkTetGenReader();
  ~vtkTetGenReader() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  std::string FileName;

private:
  vtkTetGenReader(const vtkTetGenReader&) = delete;
  void operator=(const vtkTetGenReader&) = delete;
};

#endif

/**
 * @file   vtkSoftBodyOutputPort.h
 * @brief  The Soft Body filter's output ports by name. The numbers are those of the XML's
 *         OutputPort elements and of saved states, so they never change.
 */
#ifndef vtkSoftBodyOutputPort_h
#define vtkSoftBodyOutputPort_h

enum class vtkSoftBodyOutputPort : int
{
  Mesh = 0,        ///< vtkUnstructuredGrid: the input grid, moved
  Particles = 1,   ///< vtkPolyData: one vertex per point
  Convergence = 2, ///< vtkTable: the residual per iteration of the frame's last step
  Surface = 3,     ///< vtkPolyData: the Surface input skinned onto the body
  Floor = 4,       ///< vtkPolyData: the floor plane as a square
  Timings = 5,     ///< vtkTable: the wall time of each stage, per simulated frame
  Count = 6
};

/// The port's number, for the VTK calls that take an int.
constexpr int vtkSoftBodyPortNumber(vtkSoftBodyOutputPort port)
{
  return static_cast<int>(port);
}

#endif

/**
 * @class   vtkSoftBodyDistribution
 * @brief   Under MPI, turns the pieces of a body that a reader or RedistributeDataSet spread over
 *          the ranks back into whole bodies, and spreads whole bodies over the ranks.
 *
 * Simulating each rank's piece alone tears a body apart (each piece falls on its own, its mass
 * is a fraction of the body's, the interface points end at different places on each rank).
 * Instead, every rank sends its piece to rank 0 (ghost cells dropped); rank 0 appends them,
 * merging the interface points the pieces share (points at exactly the same coordinates are
 * one point), splits the result into bodies (connected components: cells sharing a point) and
 * deals whole bodies to the ranks, largest first to the least loaded rank. Each rank then
 * simulates only its bodies; a rank without a body outputs nothing. When the bodies collide with
 * each other (`together`), they are all dealt to rank 0: bodies on different ranks could not
 * meet, and the result would differ from the serial one.
 *
 * All ranks must call LocalBodies() together (it communicates). It redistributes only when the
 * piece of some rank changed (a collective decision, so no rank waits on another), so a time
 * request with an unchanged input costs one small reduction.
 *
 * The result equals the serial one up to rounding: the gathered body's points are in another
 * order than the serial input's, which changes the order of floating-point sums.
 */
#ifndef vtkSoftBodyDistribution_h
#define vtkSoftBodyDistribution_h

#include "vtkSmartPointer.h"
#include "vtkType.h"

class vtkMultiProcessController;
class vtkUnstructuredGrid;

class vtkSoftBodyDistribution
{
public:
  /// The controller of a parallel run (pvbatch / pvserver under MPI), or null when the process
  /// runs alone.
  static vtkMultiProcessController* ParallelController();

  /// This rank's whole bodies from this rank's piece; empty on ranks without a body. With
  /// `together`, every body goes to rank 0.
  vtkUnstructuredGrid* LocalBodies(
    vtkUnstructuredGrid* piece, vtkMultiProcessController* controller, bool together);

  /// Bodies found and dealt at the last redistribution (the same on every rank).
  int GetNumberOfBodies() const { return this->NumberOfBodies; }

  /// Whether the last LocalBodies() call redistributed (every rank answers the same).
  bool Redistributed() const { return this->LastRedistributed; }

private:
  void Redistribute(vtkUnstructuredGrid* piece, vtkMultiProcessController* controller, bool together);

  const vtkUnstructuredGrid* Piece = nullptr; // identity only, never dereferenced
  vtkMTimeType PieceMTime = 0;
  vtkSmartPointer<vtkUnstructuredGrid> Local;
  int NumberOfBodies = 0;
  bool Together = false;
  bool LastRedistributed = false;
};

#endif

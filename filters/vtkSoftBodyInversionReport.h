/**
 * @class   vtkSoftBodyInversionReport
 * @brief   Tets turned inside out during a run, counted in every Soft Body mesh output.
 *
 * A tet whose VolumeRatio is <= 0 is inverted. Every output frame carries the count as field
 * data "InvertedTets"; the first frame that has any becomes a warning, with what limits the
 * method there and what to change, so a run that crushes its tets does not do so silently.
 * (Contacts flattening a resting body's bottom layer, and a solve leaving small tets near the
 * contact unconverged, are handled in core (pbd_held_tets.cpp); what a run still inverts - too
 * few iterations or substeps for its load, a per-tet Young's modulus at one substep, a
 * mass-spring material too soft for its load - is said here. Tets a breaking run has broken are
 * not counted: they no longer hold their volume.)
 */
#ifndef vtkSoftBodyInversionReport_h
#define vtkSoftBodyInversionReport_h

#include "vtkSoftBodyFilter.h"

#include "softbody/pbd/pbd_simulation.h"

#include <string>
#include <vector>

class vtkFieldData;

struct vtkSoftBodyInversionReport
{
  /// How many of `ratios` (one per tet, in the simulation's tet order) are <= 0, leaving out
  /// the tets `pbd` (null for mass-spring) has broken.
  static std::size_t Count(const std::vector<double>& ratios, const softbody::PbdSimulation* pbd);
  /// Adds field data "InvertedTets" (the count) to `field`.
  static void AddField(std::size_t inverted, vtkFieldData* field);
  /// Empty when nothing is inverted; else the count at `time`, the cause and the remedy for
  /// the method and values of `p` (quoted).
  static std::string Warning(std::size_t inverted, std::size_t tets, double time,
    const vtkSoftBodyFilter::Parameters& p);
};

#endif

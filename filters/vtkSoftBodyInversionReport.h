/**
 * @class   vtkSoftBodyInversionReport
 * @brief   Tets turned inside out during a run, counted in every Soft Body mesh output.
 *
 * A tet whose VolumeRatio is <= 0 is inverted. Every output frame carries the count as field
 * data "InvertedTets"; the first frame that has any becomes a warning, with what limits the
 * method there and what to change, so a run that crushes its tets does not do so silently.
 * (The inverted tets of issue 14's resting ellipsoid were the floor's contacts flattening the
 * bottom layer; those are gone. What remains at PBD/XPBD's default 10 iterations x 1 substep
 * is the solve not carrying a resting body's support up through it within one step: a few
 * small tets near the contact, none with 4 substeps. Mass-spring's springs and linear volume
 * term do not bar inversion when the load is large against YoungsModulus.)
 */
#ifndef vtkSoftBodyInversionReport_h
#define vtkSoftBodyInversionReport_h

#include "vtkSoftBodyFilter.h"

#include <string>
#include <vector>

class vtkFieldData;

struct vtkSoftBodyInversionReport
{
  /// How many of `ratios` (one per tet; NaN for cells that are not tets) are <= 0.
  static std::size_t Count(const std::vector<double>& ratios);
  /// Adds field data "InvertedTets" (the count) to `field`.
  static void AddField(std::size_t inverted, vtkFieldData* field);
  /// Empty when nothing is inverted; else the count at `time`, the cause and the remedy for
  /// the method and values of `p` (quoted).
  static std::string Warning(std::size_t inverted, std::size_t tets, double time,
    const vtkSoftBodyFilter::Parameters& p);
};

#endif

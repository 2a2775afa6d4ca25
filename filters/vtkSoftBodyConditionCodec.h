/**
 * @brief   A condition's description as field data: written by Soft Body Condition onto its
 *          output, read back by the Soft Body filter from its Conditions input.
 *
 * Everything but the set travels here (the set is the output's points, matched by position).
 * Angles are in degrees, as the user typed them; the rest in SI units.
 */
#ifndef vtkSoftBodyConditionCodec_h
#define vtkSoftBodyConditionCodec_h

#include "softbody/scene/conditions.h"

#include <string>
#include <vector>

class vtkFieldData;

namespace vtkSoftBodyConditionCodec
{
/// Adds the arrays describing `condition` (its points excepted) to `field`.
void Encode(const softbody::Condition& condition, vtkFieldData* field);

/// Whether `field` carries a condition (the output of a Soft Body Condition).
bool HasCondition(vtkFieldData* field);

/// Adds, per condition and per value a Soft Body Condition property holds (Translation,
/// RotationAngle, Force, Pressure, PullTarget, PullStiffness, ...), an array named
/// "ConditionValues NAME PROPERTY" with one tuple per entry of `overTheRun` (the values from
/// frame 0, then after each change made during playback): what softbody.keyframes turns into
/// animation keyframes, so a live session can be replayed and saved.
void EncodeValuesOverTheRun(const std::vector<std::vector<softbody::Condition>>& overTheRun, vtkFieldData* field);

/// Fills `condition` (its points left empty) from `field`; a message naming what is missing or
/// malformed, empty on success.
std::string Decode(vtkFieldData* field, softbody::Condition& condition);
}

#endif

// From one point's narrow-phase candidates to its contacts: one contact per touched feature,
// in the ContactSet order.
#pragma once

#include "softbody/collision/narrow_phase.h"

#include <cstdint>
#include <vector>

namespace softbody
{

/// The order of ContactSet: point, kind, source, then the other points (or triangle).
bool contactBefore(const Contact& x, const Contact& y);

/// One point's candidates -> its contacts. Against one surface a point near an edge or corner
/// finds that feature through every triangle around it, and near a face also finds the
/// face's neighbours' edges; one contact per feature is wanted (the same constraint twice would
/// mean twice the friction). Per (kind, source), nearest first: every contact on a face is kept
/// (a point in a concave corner touches both faces); an edge or corner contact is kept unless
/// a nearer (or equally near) kept contact lies on a triangle sharing a vertex with its
/// triangle (the same feature, or the face next to it, covers it). A ridge nearer than the
/// face it stands on is kept, and so are contacts on parts of the surface that share no vertex
/// (a point between two fingers). Ties go by key, so the choice does not depend on the
/// candidates' order.
/// `order` and `kept` are scratch (kept between calls to spare allocations).
void reduceCandidates(std::vector<ContactCandidate>& found, std::vector<std::uint32_t>& order,
  std::vector<std::uint32_t>& kept, ContactSet& out);

} // namespace softbody

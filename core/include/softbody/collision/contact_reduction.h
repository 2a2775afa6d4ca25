// From one point's narrow-phase candidates to its contacts: one contact per touched feature,
// in the ContactSet order.
#pragma once

#include "softbody/collision/narrow_phase.h"

#include <cstdint>
#include <vector>

namespace softbody
{

/// The most contacts one point keeps against one source (one obstacle, one other body, or its
/// own body, per kind). A point on a surface touches at most three faces at once (a concave
/// corner of it) and stands in front of their shared edges and corner; a fourth covers a
/// speculative contact of a fast point. Nearer ones are kept first.
constexpr std::size_t kMostContactsPerSource = 4;

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
/// A point behind faces of a body's surface that it was behind at the start of the substep too
/// (inside a closed body, or across cloth) keeps only the nearest of them (faces it crossed in
/// the substep are all kept): it leaves through that face, and the faces farther behind it are the far
/// side of the body, whose contacts would push it the other way (two tori started one inside
/// the other: points caught by faces on both sides of a tube, pushed to and fro, every
/// substep faster, until each point held a thousand contacts). And each group keeps its
/// kMostContactsPerSource nearest contacts only, so the cost of the reduction and of the
/// contact solve per point is bounded whatever the broad phase returns.
/// `order` and `kept` are scratch (kept between calls to spare allocations).
void reduceCandidates(std::vector<ContactCandidate>& found, std::vector<std::uint32_t>& order,
  std::vector<std::uint32_t>& kept, ContactSet& out);

} // namespace softbody

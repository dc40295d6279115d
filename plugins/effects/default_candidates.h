// The effect library's candidates for the physics finder (model/effect_candidates.h): each effect
// on one joint, rod pair, camera or target at a time, so that a finding names where it acts.
#pragma once

#include <vector>

#include "cellmetry/model/effect_candidates.h"

namespace cellmetry::effects {

std::vector<OfferedCandidate> OfferCandidates(const CandidateCell& cell);

}  // namespace cellmetry::effects

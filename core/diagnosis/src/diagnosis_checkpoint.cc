// A diagnosis's finished rounds, as JSON in a checkpoint and back (diagnosis_checkpoint.h).
#include "diagnosis_checkpoint.h"

#include <limits>

#include <nlohmann/json.hpp>

#include "cellmetry/formats/checkpoint.h"

namespace cellmetry {

// Every field, so that a resumed round is the round that finished. JSON has no NaN: a
// non-finite number is written as null, and null reads back as NaN (RestoreNonFinite).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ScalarEstimate, name, unit, nominal, value, sigma,
                                   sigma_statistical, sigma_systematic, sigma_inputs, held,
                                   undetermined, convention)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(LookAlike, label, correlation)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SignaturePoint, camera, axis, predicted_mm, before_mm, after_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CandidateFinding, name, label, site, testable,
                                   untestable_because, data_needed, unabsorbed, detectable, dof,
                                   score, p_holm, refitted, likelihood_ratio, p_lr_holm, delta_bic,
                                   cv_rms_mm, cv_gain, cv_gain_se, bootstrap_share, bootstrap_rival,
                                   bootstrap_rival_effect, rival_p, rival, rival_effect,
                                   look_alikes, aliases, alias_names, implausible, explained_share,
                                   failed, accepted)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DiagnosisRound, dispersion, candidates, accepted, frames)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AcceptedEffect, name, label, site, group, group_label,
                                   description, parameters, peak_mm, aliases, alias_names,
                                   look_alikes, signature, held_out_sigma_before,
                                   held_out_sigma_after, role, group_share, headline_correlation,
                                   site_correlations, stronger_implausible, frame)

namespace {

// Nulls back to NaN: in these records only a number is ever written as null.
void RestoreNonFinite(nlohmann::json* j) {
  if (j->is_null()) {
    *j = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  if (j->is_structured()) {
    for (auto& item : *j) RestoreNonFinite(&item);
  }
}

std::string Key(int index) { return "round/" + std::to_string(index); }

}  // namespace

RoundLog::RoundLog(Checkpoint* checkpoint) : checkpoint_(checkpoint) {}

std::optional<RoundRecord> RoundLog::Finished(int index) const {
  if (!checkpoint_) return std::nullopt;
  const nlohmann::json* found = checkpoint_->Find(Key(index));
  if (!found) return std::nullopt;
  nlohmann::json j = *found;
  RestoreNonFinite(&j);
  RoundRecord record;
  try {
    j.at("round").get_to(record.round);
    if (j.contains("accepted")) record.accepted = j.at("accepted").get<AcceptedEffect>();
    j.at("untestable").get_to(record.untestable);
    j.at("done").get_to(record.done);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;  // written by another version: the round runs again
  }
  return record;
}

void RoundLog::Keep(int index, const RoundRecord& record) {
  if (!checkpoint_) return;
  nlohmann::json j = {
      {"round", record.round}, {"untestable", record.untestable}, {"done", record.done}};
  if (record.accepted) j["accepted"] = *record.accepted;
  checkpoint_->Put(Key(index), std::move(j));
}

}  // namespace cellmetry

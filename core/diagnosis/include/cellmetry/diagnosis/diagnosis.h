// DiagnoseWorkcell: the physics finder. After the geometric fit, locate where the recording and
// the model disagree, name the physics left out, model it, and show the held-out fit improve, or
// say that the residuals are noise, or that what remains matches nothing in the library.
//
//   1. noise floor: the job's sigma or the repeatability of repeated captures (noise_model.h);
//      without either there is no floor to test against, and that is an InputError
//   2. the geometric fit; chi-square of its residuals against the floor
//   3. where: the partial correlation of the residuals with every regressor the recording offers
//      (joint angles, gravity torques, approach directions, capture order, time, temperature,
//      payload, depth, image position), after removing what the geometry explains; Durbin-Watson
//      in capture order
//   4. per candidate effect: the part of its signature (its Jacobian columns) outside the span
//      of the geometric Jacobian; an effect whose signature the geometry absorbs, or whose facts
//      the recording lacks, is "untestable here", with the data that would make it testable.
//      Every candidate's columns come from one linearization per round (the current model with
//      all candidates at zero, differentiated with respect to theirs alone)
//   5. greedy selection, one effect per round, every statistic divided by the dispersion (the
//      current fit's chi-square/dof, at least 1: quasi-likelihood, so that on a recording whose
//      mismatch is mostly unexplained an effect must explain a share of what is left, not beat
//      the floor). Every testable candidate gets its score statistic
//      (the likelihood-ratio test to first order, from one Jacobian, Rao 1948); the best
//      `refits` are refitted in full (nonlinear); a refit whose size is beyond its physics'
//      plausible range (Parameter::plausible) yields to any plausible one. The best refit is
//      accepted only if
//        0. its size is plausible: an implausible one is never reported as that physics; the
//           report says its size rules it out and names what shares its signature,
//        a. its likelihood-ratio test passes at `alpha` after Holm's correction over the round,
//        b. BIC falls (n = the poses, the independent units),
//        c. blocked cross-validated RMS (folds of whole poses; normalized by sigma, so that every
//           axis weighs by its significance) falls by more than its standard error over folds,
//        c'. it removes at least `min_explained_share` of the held-out excess over the floor,
//           where that excess is beyond chance (a sliver of a large mismatch is not a finding),
//           and does not make the held-out positions worse (by more than 1 %),
//        d. (`selection_test` "rivals") every candidate outside its group (CandidateEffect::
//           group: nested variants of the same physics, or the forms of one camera's
//           calibration) and its aliases is rejected at `alpha` as the cause of what the chosen
//           one explains (RivalTestPAt, diagnosis_linear.h, `rival_draws` draws and 20 times
//           as many where p is near alpha: Cox 1962, Williams 1970; all of them
//           together an intersection-union test, Berger 1982), leaving out any rival that,
//           as the cause, would need a sign its physics cannot have (a negative clearance is
//           no rival); where one is not rejected, the report names it and
//           proposes `cellmetry plan` for the two (pose_plan.h), whose poses tell them apart.
//           ("bootstrap", the other gate: its group included in >=
//           `bootstrap_share` of bootstrap resamples of poses, each running the greedy
//           selection, BIC-gated, on the resampled linearization, Sauerbrei & Schumacher 1992;
//           the share is reported either way);
//      candidates whose unabsorbed signatures correlate >= `alias_correlation` with the chosen
//      one are its aliases: one finding with two names, counted with it by either test and
//      named together in the report;
//      rounds stop when no candidate passes them all: the residuals are then consistent with the
//      floor as far as the library can tell (the omnibus chi-square is reported too, but one
//      effect among thousands of residual rows barely moves it)
//   6. what remains: structured (a regressor still correlates with the residuals, Bonferroni
//      at `alpha`, or the chi-square exceeds the floor) along the strongest regressor, or noise
//   7. physical findings: accepted effects acting at the same site (one joint, one camera, one
//      target) are one finding. Its headline is the member accepted first: in that round it was
//      the strongest single description refitted, the others at zero. A later member at the
//      same site is separate physics only if it removes at least `min_group_share` of the
//      held-out excess the whole group removes (mean square in sigmas, each member's gain at
//      its own acceptance), or if, smaller, its signature is unlike the headline's (canonical
//      correlation below `shape_correlation` of what the geometry leaves of the two, in the
//      headline's round: a backlash beside a compliance). Otherwise it is the residual shape
//      of the headline's physics (a stiffening spring fitted as compliance leaves a misfit a
//      few percent of its size, a function of the same load, and the gear error of the same
//      joint, which looks like the compliance, soaks it up): reported with the finding, not as
//      physics. What is fitted does not change.
//
// Candidates (default): what the loaded effect plugins offer for the cell
// (model/effect_candidates.h). The effect library offers, for every robot joint,
// joint_compliance, backlash, transmission_error (harmonic 1, harmonic 2, and all of 1, 2 and
// the configured gear harmonics together) and joint_scale, each on that joint alone;
// thermal_drift (by temperature, or the warm-up model when the recording has only times);
// per camera depth_bias (scale, tilt) and camera_intrinsics (focal, principal point, radial
// distortion k1, each alone, and the whole lens: k1, k2, p1, p2); per target target_scale, and
// target_tilt where its rotation is measured; world_frame where there is a world target
// (plugins/effects/default_candidates.cc).
#pragma once

#include <array>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct DiagnosisOptions {
  double alpha = 0.01;              // family-wise error rate of every test
  int bootstrap = 40;               // resamples of poses
  double alias_correlation = 0.99;  // candidates this alike are one finding with two names
  double bootstrap_share = 0.8;     // how often their selection must include the chosen effect
  // What tells the chosen effect from the other candidates: "rivals" (every other group's
  // member rejected as the cause at `alpha` by a parametric test of non-nested models, an
  // intersection-union test: Berger 1982) or "bootstrap" (its group included in at least
  // `bootstrap_share` of the resamples; docs/physics.md).
  std::string selection_test = "rivals";
  int rival_draws = 2000;  // parametric draws per rival for "rivals" (20x near alpha)
  int folds = 10;          // blocked cross-validation, by pose (10: the standard error
                           // of the gain is steadier than with 5)
  int refits = 3;          // best candidates by score refitted in full each round
  // Testable: a candidate at its plausible size would pass the score test at `alpha` alone
  // (CandidateFinding::detectable above the chi-square(1) quantile), however much of its
  // signature the geometry absorbs; with fewer than this share of it outside the geometry's
  // span (or, without a plausible size, below min_unabsorbed_share), it is untestable.
  double min_unabsorbed = 1e-4;        // numerical floor: less is rounding, not signature
  double min_unabsorbed_share = 0.05;  // the rule for a candidate without a plausible size
  double min_explained_share = 0.1;    // of the held-out excess over the floor an accepted effect
                                       // must remove, where the excess is beyond chance; less is
                                       // a sliver of something else, reported as unexplained
  double min_group_share = 0.1;        // of the held-out excess its site's finding removes, a
                                       // further effect at the same site must remove to be named
                                       // as separate physics (step 7)
  double shape_correlation = 0.5;      // ... unless unlike the headline: below this correlation
                                       // with its signature, a smaller effect is separate too
  // Also the candidates that act on every camera at once (each form of a camera's calibration)
  // and on every target (their printed sizes, separately and from one printer): a cause the
  // cameras or boards share, tested as one. Off by default: more candidates are more rivals,
  // and on the physics suite they cost single-site names (docs/physics.md).
  bool group_candidates = false;
  int max_effects = 4;
  int min_poses = 20;                  // fewer: too few samples for the tests
  std::vector<double> link_masses_kg;  // gravity-torque regressor (default 1 kg per link)
  std::vector<int> gear_harmonics;     // of the drives, beyond 1 and 2 (e.g. a gearbox's stages)
  // Joints the drives couple mechanically, {driving, driven} and 1-based (a Staubli wrist's
  // {5, 6}): each offered as the coupling the controller may take out wrongly.
  std::vector<std::array<int, 2>> joint_couplings;
};

// One candidate: an effect plugin instance on one joint, camera or the whole arm.
struct CandidateEffect {
  WorkcellEffect effect;  // name, robot, plugin
  std::string type;       // the plugin's type, "backlash"
  std::string label;      // "joint 2 backlash"
  std::string data_hint;  // what data separates it from the geometry ("a wider joint 2 range")
  // The physics it names, shared by nested variants of it ("ur3.transmission_j4" for harmonic 1,
  // harmonic 2 and both) and by its forms ("ur3.thermal" for growth with the recorded
  // temperature and while warming up in time): the bootstrap counts a resample won by any of
  // them as won by the family, since they name the same physics at the same site. Empty:
  // effect.name.
  std::string family;
  const std::string& family_name() const { return family.empty() ? effect.name : family; }
  // One physical cause that several library forms (or families) describe: a camera's
  // calibration as its pose estimator and depth use it ("camera.calibration_cam2": its depth
  // scale and tilt, focal length, principal point, lens distortion, k1 alone or with k2, p1 and
  // p2 (those two one family); a real calibration error mixes them).
  // The bootstrap counts a resample won by any member as won by the group, and the report names
  // the group with the chosen form as its best single description. Unlike a family, the other
  // members stay candidates after one is accepted: a camera can be off in two ways. Empty: the
  // family is the group.
  std::string group;
  std::string group_label;  // "cam2 calibration", shown with the chosen form's description
  const std::string& group_name() const { return group.empty() ? family_name() : group; }
  // Where it acts, in words ("ur3 joint 3", "camera cam2", "target tool"): accepted effects at
  // one site are one physical finding (step 7). Empty: a site of its own (thermal growth).
  std::string site;
  // What it fits, as physics at a site ("principal point/cam2"): a candidate that acts on
  // several cameras or targets together ("every camera's principal point") has one atom each.
  // Two candidates with an atom in common fit the same thing: once one is accepted the other
  // leaves the rounds, and neither is the other's rival (one contains the other).
  std::vector<std::string> atoms;
  // Where the answer is read, not what it predicts: the world tag's tilt from the placement's
  // frame, which a robot stated level determines. It moves the frames the answer gives, and no
  // prediction the held-out error could see, so it is judged by its tests of significance and
  // size alone, after the rounds (a frame in `accepted`, AcceptedEffect::frame).
  bool frame = false;
};

// Whether `a` and `b` would fit the same thing: one family, or an atom in common.
bool Overlap(const CandidateEffect& a, const CandidateEffect& b);

// The site (CandidateEffect::site) of an effect configured by `config` on `robot`: its one joint,
// arm, camera or target; "" where it names none or several.
std::string CandidateSite(const ConfigNode& config, const std::string& robot);

// Another candidate whose unabsorbed signature this pose set can hardly tell apart from one's own.
struct LookAlike {
  std::string label;
  double correlation = 0.0;  // largest canonical correlation of the unabsorbed signatures
};

struct CandidateFinding {
  std::string name;
  std::string label;
  std::string site;  // CandidateEffect::site ("" where it has none)
  bool testable = true;
  std::string untestable_because;  // "98 % absorbed by the geometry", "no temperatures", ...
  std::string data_needed;         // what would make it testable
  double unabsorbed = 0.0;         // share of the signature's norm outside the geometry's span
  // The score statistic the candidate would add at its plausible size (each parameter at its
  // Parameter::plausible, the direction the poses show best), over the dispersion: what the
  // data could tell of it. NaN where a parameter has no plausible size.
  double detectable = 0.0;
  int dof = 0;         // its free parameters
  double score = 0.0;  // score statistic (chi-square, dof)
  double p_holm = 1.0;
  bool refitted = false;
  double likelihood_ratio = 0.0;  // chi-square drop of the full refit, over the dispersion
  double p_lr_holm = 1.0;
  double delta_bic = 0.0;
  double cv_rms_mm = 0.0;              // held-out RMS with it, mm
  double cv_gain = 0.0;                // held-out normalized RMS without it minus with it (sigmas)
  double cv_gain_se = 0.0;             // standard error of that gain over the folds
  double bootstrap_share = 0.0;        // resamples whose selection included its group
  std::string bootstrap_rival;         // the other group included most often ("" if none)
  std::string bootstrap_rival_effect;  // its member included most often, by name: what
                                       // `cellmetry plan --effect` takes to tell the two apart
  double rival_p = 0.0;                // with selection_test "rivals": the largest p of the rival
  std::string rival;                   // test over the other groups' members, that member's label
  std::string rival_effect;            // and its name (what `cellmetry plan --effect` takes)
  // The round's chosen one's look-alikes: correlation >= 0.8, strongest first.
  std::vector<LookAlike> look_alikes;
  std::vector<std::string> aliases;      // of those, the ones >= alias_correlation (labels)
  std::vector<std::string> alias_names;  // the same, by candidate name
  std::string implausible;               // refitted: a size beyond its physics' plausible range, in
                            // words ("" when plausible); never accepted as that physics
  double explained_share = 1.0;     // of the held-out excess over the floor, what it removes
  std::vector<std::string> failed;  // the round's chosen one: tests it failed, of "size",
                                    // "LR", "BIC", "CV", "share", "positions", "bootstrap",
                                    // "rivals"
  bool accepted = false;
};

struct RegressorFinding {
  std::string regressor;             // "joint 2 gravity torque"
  std::string axis;                  // x, y, depth, or "x, y and depth" (tested together)
  double partial_correlation = 0.0;  // the three axes together: the RMS of theirs, unsigned
  double p_value = 1.0;              // Bonferroni over all regressors and axes
};

struct DiagnosisRound {
  double dispersion = 1.0;                   // chi-square/dof of the model the round starts from
                                             // (>= 1); every test statistic is divided by it
  std::vector<CandidateFinding> candidates;  // testable ones, best score first
  std::string accepted;                      // "" when none passed
  bool frames = false;                       // the frames' step (CandidateEffect::frame)
};

// One carried-target position row seen along an accepted effect: what the effect predicts there
// and the residual (prediction - measurement, camera axis `axis`) before and after it was fitted.
// Before, a real effect shows as residual = -predicted (less what the geometry absorbed); after,
// as a flat band. The report plots it (core/report).
struct SignaturePoint {
  std::string camera;
  int axis = 0;  // 0 x, 1 y, 2 depth
  double predicted_mm = 0.0;
  double before_mm = 0.0;
  double after_mm = 0.0;
};

struct AcceptedEffect {
  std::string name;
  std::string label;        // the candidate's ("joint 3 compliance")
  std::string site;         // CandidateEffect::site
  std::string group;        // CandidateEffect::group ("" when it has none)
  std::string group_label;  // CandidateEffect::group_label
  std::string description;  // Effect::Describe at the estimate
  std::vector<ScalarEstimate> parameters;
  double peak_mm = 0.0;                  // largest tool displacement it predicts
  std::vector<std::string> aliases;      // candidates these poses cannot tell from it
  std::vector<std::string> alias_names;  // the same, by candidate name
  // Candidates whose unabsorbed signatures correlate >= 0.8 with its own in the round it was
  // accepted (its aliases among them), strongest first: where the name could be another's.
  std::vector<LookAlike> look_alikes;
  std::vector<SignaturePoint> signature;  // rows it moves by more than 1e-9 mm
  // The model's held-out RMS in sigmas just before and after it was accepted (same folds).
  double held_out_sigma_before = 0.0, held_out_sigma_after = 0.0;
  // Its physical finding (step 7): "headline", "separate" (passed its test against the group)
  // or "residual shape" (did not); and the share of the group's held-out excess it removed.
  std::string role = "headline";
  double group_share = 1.0;
  double headline_correlation = 1.0;  // its signature's with the headline's (site_correlations)
  // In the round it was accepted, the canonical correlation of what the model then (geometry
  // and the effects accepted before) leaves of its signature with what it leaves of every other
  // testable candidate at its site, by candidate name.
  std::map<std::string, double> site_correlations;
  // In its round, the refits that explained more than it but at a size their physics cannot
  // have (CandidateFinding::implausible), strongest first: "label: why". Set aside as names and
  // as rivals, they say the mismatch along this signature may be larger than its name explains.
  std::vector<std::string> stronger_implausible;
  // A frame (CandidateEffect::frame), accepted on its likelihood-ratio test and size alone.
  bool frame = false;
};

// Accepted effects at one site, as one physical finding (step 7); indices into
// DiagnosisResult::accepted, in the order they were accepted.
struct PhysicalFinding {
  std::string site;  // "" for a headline of no single site
  int headline = 0;
  std::vector<int> separate;             // passed their test against the group
  std::vector<int> residual_shape;       // did not: the headline physics' shape
  double held_out_excess_removed = 0.0;  // by the whole group (mean square in sigmas)
};

struct FitSummary {
  double chi2 = 0.0;        // of the measurements
  double prior_chi2 = 0.0;  // what the job's stated priors add (a level base's
                            // tilt over its sigma, squared)
  double dof = 0.0;
  double p_value = 1.0;  // chi-square against the floor
  double rms_mm = 0.0;   // carried targets' positions
  double held_out_rms_mm = 0.0;
  double held_out_rms_se_mm = 0.0;  // HeldOut::total_se_mm
  double held_out_sigma = 0.0;      // held-out RMS in sigmas over every carried-target
                                    // row the fit uses (rotations too)
  bool consistent_with_noise() const { return p_value > 0.01; }
};

struct DiagnosisResult {
  std::string noise_source;
  double floor_rms_mm = 0.0;                    // RMS of the noise sigma over the same rows
  FitSummary geometric;                         // the geometry alone
  FitSummary final;                             // with the accepted effects
  HeldOutGain held_out_gain;                    // geometric -> final held-out RMS
  std::map<std::string, double> durbin_watson;  // axis -> statistic, capture order
  std::vector<RegressorFinding> regressors;     // strongest first
  std::vector<CandidateFinding> untestable;
  std::vector<DiagnosisRound> rounds;
  std::vector<AcceptedEffect> accepted;
  std::vector<PhysicalFinding> findings;  // the accepted effects grouped by site (step 7)
  double min_group_share = 0.1;           // the options' (the report states them)
  double shape_correlation = 0.5;
  std::string unexplained;  // "" or where structure remains, in words
  WorkcellResult final_fit;
  WorkcellProblem final_spec;  // what final_fit identified: the job's cell and
                               // every accepted effect
  std::string job;             // the job diagnosed (`origin`), for the commands
                               // the report proposes
};

// The default candidate list for `spec`'s robots and `recording`'s cameras: every candidate the
// registry's effect plugins offer (Registry::candidate_offers), built by the registry; the
// offers see `options.link_masses_kg` (empty: 1 kg per link), `options.gear_harmonics`,
// `options.joint_couplings` and `options.group_candidates`.
std::vector<CandidateEffect> DefaultCandidates(const WorkcellProblem& spec,
                                               const Recording& recording,
                                               const DiagnosisOptions& options, Registry& registry);

// Groups `result`'s accepted effects into physical findings (step 7): fills `findings` and each
// accepted effect's role and group share. DiagnoseWorkcell calls it.
void GroupFindings(const DiagnosisOptions& options, DiagnosisResult* result);

class Checkpoint;

// Raises InputError (naming `origin`) for too few poses or no noise floor. With `checkpoint`,
// each round is kept in it as it finishes and a round finished before is read back instead of
// run again (the accepted effects refitted, one fit each): an interrupted diagnosis resumes with
// the same answer. The checkpoint's fingerprint must cover every input (job and recording).
DiagnosisResult DiagnoseWorkcell(const WorkcellProblem& spec, const Recording& recording,
                                 const SolverMaker& make_solver,
                                 const std::vector<CandidateEffect>& candidates,
                                 const DiagnosisOptions& options, const std::string& origin,
                                 Checkpoint* checkpoint = nullptr);

// The finding in words a robot engineer reads in ten seconds.
std::string DiagnosisReport(const DiagnosisResult& result);
// What to record next where a candidate of the last round failed only the bootstrap, against a
// rival, having won at least a fifth of the resamples: "To tell it from <rival>, record the
// poses `cellmetry plan <job> --effect <it> --effect <rival>` proposes and diagnose again."
// ("" otherwise). Part of DiagnosisReport, under each such candidate; the first overload gives
// the first such candidate's (report.html's summary line).
std::string PlanAgainstRivalAdvice(const DiagnosisResult& result);
std::string PlanAgainstRivalAdvice(const DiagnosisResult& result,
                                   const CandidateFinding& candidate);
// Where the last round's closest candidate failed only the test against its rival and the rival
// acts at the same joint or camera: "Tied at <site>: <it> or <rival>. ..." ("" otherwise). Part
// of DiagnosisReport, report.html's summary and diagnosis.json's `tie`.
std::string DiagnosisTie(const DiagnosisResult& result);
// The same two by candidate name (the closest first); empty where there is no tie.
std::vector<std::string> TiedCandidates(const DiagnosisResult& result);
nlohmann::json DiagnosisJson(const DiagnosisResult& result);

}  // namespace cellmetry

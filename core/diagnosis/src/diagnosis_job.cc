// Diagnosis jobs (diagnosis_job.h): the workcell job plus its optional `diagnosis:` section, and
// the candidate effects it lists (the default library when it lists none).
#include "cellmetry/diagnosis/diagnosis_job.h"

#include <algorithm>
#include <string>
#include <vector>

namespace cellmetry {
namespace {

// `joint_couplings: [[5, 6]]`: pairs of distinct joints, {driving, driven}, that some robot of
// the cell has.
void ReadJointCouplings(const ConfigNode& list, const WorkcellProblem& spec,
                        DiagnosisOptions* options) {
  int most_joints = 0;
  for (const WorkcellRobot& robot : spec.robots) {
    most_joints = std::max(most_joints, robot.model->num_joints());
  }
  for (const auto& pair : list.Elements()) {
    const std::vector<ConfigNode> joints = pair.Elements();
    if (joints.size() != 2) {
      throw pair.Error("a coupling is two joints, [driving, driven]", "e.g. [5, 6]");
    }
    const int driving = joints[0].AsInt(), driven = joints[1].AsInt();
    for (const ConfigNode& joint : joints) {
      const int j = joint.AsInt();
      if (j < 1 || j > most_joints) {
        throw joint.Error("no joint " + std::to_string(j) + " on the cell's robots (" +
                              std::to_string(most_joints) + " joints at most)",
                          "Joints are numbered from 1");
      }
    }
    if (driving == driven) throw pair.Error("a joint does not couple to itself", "e.g. [5, 6]");
    options->joint_couplings.push_back({driving, driven});
  }
}

// How the finder tests and selects: its level, resamples, draws, folds and rounds.
void ReadTestOptions(const ConfigNode& d, DiagnosisOptions* options) {
  DiagnosisOptions& o = *options;
  o.alpha = d.GetDouble("alpha", o.alpha);
  if (!(o.alpha > 0 && o.alpha < 1)) throw d["alpha"].Error("must be between 0 and 1");
  // Each resample is a selection of its own: beyond 10,000 the run is hours and the share's
  // Monte Carlo error 0.5 % already.
  o.bootstrap = d.GetIntIn("bootstrap", o.bootstrap, 0, 10000,
                           "40 resamples is the default; 10,000 the most");
  o.bootstrap_share = d.GetDoubleIn("bootstrap_share", o.bootstrap_share, 0.0, 1.0,
                                    "A share of resamples: 0.8 is the default");
  o.selection_test = d.GetString("selection_test", o.selection_test);
  if (o.selection_test != "bootstrap" && o.selection_test != "rivals") {
    throw d["selection_test"].Error("unknown selection test '" + o.selection_test + "'",
                                    "Use bootstrap or rivals");
  }
  o.rival_draws = d.GetIntIn("rival_draws", o.rival_draws, 100, 1000000,
                             "Use 100 or more draws; 2000 is the default");
  o.folds = d.GetIntIn("folds", o.folds, 2, 1000, "10 is the default; 2 the fewest");
  o.max_effects = d.GetIntIn("max_effects", o.max_effects, 1, 100,
                             "4 is the default: each round names one effect");
  o.min_poses = d.GetIntIn("min_poses", o.min_poses, 1, 1000000,
                           "20 is the default: fewer poses are too few for the tests");
  o.refits = d.GetIntIn("refits", o.refits, 1, 1000, "3 is the default");
}

// What a candidate must show to be named, and when two are one finding.
void ReadGateOptions(const ConfigNode& d, DiagnosisOptions* options) {
  DiagnosisOptions& o = *options;
  o.min_unabsorbed = d.GetDoubleIn("min_unabsorbed", o.min_unabsorbed, 0.0, 0.999,
                                   "A share of a signature: 1e-4 is the default");
  o.group_candidates = d.GetBool("group_candidates", o.group_candidates);
  o.alias_correlation = d.GetDouble("alias_correlation", o.alias_correlation);
  if (!(o.alias_correlation > 0 && o.alias_correlation <= 1)) {
    throw d["alias_correlation"].Error("must be in (0, 1]", "1 keeps every candidate apart");
  }
  o.min_explained_share = d.GetDouble("min_explained_share", o.min_explained_share);
  if (!(o.min_explained_share >= 0 && o.min_explained_share < 1)) {
    throw d["min_explained_share"].Error("must be in [0, 1)", "0 turns the test off");
  }
  o.min_group_share = d.GetDouble("min_group_share", o.min_group_share);
  if (!(o.min_group_share >= 0 && o.min_group_share <= 1)) {
    throw d["min_group_share"].Error("must be in [0, 1]",
                                     "0 names every effect at a site as separate physics");
  }
  o.shape_correlation = d.GetDouble("shape_correlation", o.shape_correlation);
  if (!(o.shape_correlation >= 0 && o.shape_correlation <= 1)) {
    throw d["shape_correlation"].Error("must be in [0, 1]",
                                       "0 calls every small effect at a site its residual shape");
  }
}

// What the user knows of the robot that shapes the default candidates: link masses, the gears'
// harmonics, the joints whose drives couple.
void ReadRobotKnowledge(const ConfigNode& d, const WorkcellProblem& spec,
                        DiagnosisOptions* options) {
  DiagnosisOptions& o = *options;
  if (d.Has("link_masses_kg")) {
    o.link_masses_kg = d["link_masses_kg"].AsDoubles();
    for (double m : o.link_masses_kg) {
      if (!(m >= 0 && m <= 10000)) {
        throw d["link_masses_kg"].Error("a link's mass is 0 to 10,000 kg",
                                        "Give each link's mass in kg, 0 for a massless link");
      }
    }
  }
  if (d.Has("gear_harmonics")) {
    for (const auto& h : d["gear_harmonics"].Elements()) {
      const int value = h.AsInt();
      if (value < 1) throw h.Error("a harmonic is a whole number of cycles per turn, 1 or more");
      o.gear_harmonics.push_back(value);
    }
  }
  if (d.Has("joint_couplings")) ReadJointCouplings(d["joint_couplings"], spec, &o);
}

// `candidates:`, the job's own list in place of the default library.
std::vector<ConfigNode> ReadCandidateList(const ConfigNode& d) {
  if (!d.Has("candidates")) return {};
  // These shape the default candidates, which a list replaces: taken with one, they would be
  // ignored without a word.
  for (const char* key : {"gear_harmonics", "joint_couplings", "group_candidates"}) {
    if (d.Has(key)) {
      throw d[key].Error(
          std::string("`") + key + "` shapes the default candidates, which `candidates:` replaces",
          "Drop it, or write what it would add into the `candidates:` list");
    }
  }
  return d["candidates"].Elements();
}

}  // namespace

DiagnosisJob LoadDiagnosisJob(const std::string& path, Registry& registry,
                              bool recording_must_exist) {
  DiagnosisJob job;
  job.workcell = LoadWorkcellJob(path, registry, recording_must_exist);
  const ConfigNode root = ConfigNode::LoadFile(path);
  if (!root.Has("diagnosis")) return job;
  const ConfigNode d = root["diagnosis"];
  d.ExpectKeys({"alpha", "bootstrap", "bootstrap_share", "selection_test", "rival_draws", "folds",
                "max_effects", "min_poses", "link_masses_kg", "gear_harmonics", "joint_couplings",
                "candidates", "refits", "min_unabsorbed", "alias_correlation",
                "min_explained_share", "min_group_share", "shape_correlation", "group_candidates"});
  ReadTestOptions(d, &job.options);
  ReadGateOptions(d, &job.options);
  ReadRobotKnowledge(d, job.workcell.problem, &job.options);
  job.candidate_configs = ReadCandidateList(d);
  return job;
}

std::vector<CandidateEffect> JobCandidates(const DiagnosisJob& job, const Recording& recording,
                                           Registry& registry) {
  const WorkcellProblem& spec = job.workcell.problem;
  if (job.candidate_configs.empty()) {
    return DefaultCandidates(spec, recording, job.options, registry);
  }
  std::vector<CandidateEffect> out;
  const WorkcellRobot& robot = spec.robots.front();
  for (size_t k = 0; k < job.candidate_configs.size(); ++k) {
    const ConfigNode& config = job.candidate_configs[k];
    CandidateEffect c;
    c.type = config["type"].AsString();
    c.effect.robot = robot.name;
    c.effect.effect = registry.CreateEffect(c.type, config, *robot.model);
    c.effect.config = config.FlowText();
    c.effect.name = robot.name + "." + c.type + "_" + std::to_string(k + 1);
    c.label = c.effect.effect->Describe(std::vector<double>(c.effect.effect->parameters().size()));
    c.label = c.label.substr(0, c.label.find(':'));
    c.data_hint = "poses that separate it from the geometry";
    c.site = CandidateSite(config, robot.name);
    out.push_back(c);
  }
  return out;
}

}  // namespace cellmetry

// The pose planner (pose_plan.h): candidate poses in view, their Jacobian rows at the answer,
// greedy D-optimal choice, and what it predicts.
#include "cellmetry/diagnosis/pose_plan.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "diagnosis_linear.h"

namespace cellmetry {
namespace {

// How a camera has seen the carried targets so far: the depths, and how far across and down
// the image (|x|/z, |y|/z). A pyramid, as an image is a rectangle: a cone through the farthest
// corner seen would promise views beyond the image's short side, which a real camera misses.
struct SeenRange {
  double min_depth_mm = INFINITY, max_depth_mm = 0.0, max_tan_x = 0.0, max_tan_y = 0.0;
  bool Contains(const Eigen::Vector3d& p) const {
    if (p.z() <= 0.0) return false;
    return p.z() >= 0.95 * min_depth_mm && p.z() <= 1.05 * max_depth_mm &&
           std::abs(p.x()) <= max_tan_x * p.z() && std::abs(p.y()) <= max_tan_y * p.z();
  }
};

std::map<std::string, SeenRange> SeenRanges(const Recording& recording) {
  std::map<std::string, SeenRange> seen;
  for (const auto& obs : recording.observations) {
    if (recording.targets.at(obs.target) == kWorldCarrier) continue;
    SeenRange& r = seen[obs.camera];
    const Eigen::Vector3d& p = obs.position_mm;
    if (p.z() <= 0.0) continue;  // behind the camera: not a view
    r.min_depth_mm = std::min(r.min_depth_mm, p.z());
    r.max_depth_mm = std::max(r.max_depth_mm, p.z());
    r.max_tan_x = std::max(r.max_tan_x, std::abs(p.x()) / p.z());
    r.max_tan_y = std::max(r.max_tan_y, std::abs(p.y()) / p.z());
  }
  return seen;
}

// A drawn pose and the measured poses of its robot's targets in the cameras that would see them.
struct Draw {
  PlannedPose pose;
  std::vector<Observation> observations;  // sample id filled in later
};

Draw Predict(const WorkcellRobot& robot, const WorkcellEstimate& at,
             const std::map<std::string, SeenRange>& seen, std::vector<double> q) {
  Draw draw;
  draw.pose.robot = robot.name;
  draw.pose.q = std::move(q);
  Pose T_base_flange;
  const std::vector<double>& values = at.model.at(robot.name);
  if (!robot.model->Forward(draw.pose.q.data(), values.data(), &T_base_flange)) return draw;
  for (const auto& [camera, range] : seen) {
    const auto cam = at.T_world_cam.find(camera);
    if (cam == at.T_world_cam.end()) continue;
    bool sees = false;
    for (const auto& tool : robot.tools) {
      const Pose T_cam_target = cam->second.inverse() * at.T_world_base.at(robot.name) *
                                T_base_flange * at.T_flange_target.at(tool.target);
      if (!range.Contains(T_cam_target.t)) continue;
      Observation obs;
      obs.camera = camera;
      obs.target = tool.target;
      obs.position_mm = T_cam_target.t;
      obs.rvec = RvecFromRotation(T_cam_target.R);
      draw.observations.push_back(obs);
      sees = true;
    }
    if (sees) draw.pose.cameras.push_back(camera);
  }
  return draw;
}

// Uniform draws inside the joint limits (a full turn either way where there are none), kept
// when some camera would see them.
std::vector<Draw> DrawInView(const WorkcellProblem& spec, const Recording& recording,
                             const WorkcellEstimate& at, const PosePlanOptions& options) {
  const auto seen = SeenRanges(recording);
  std::mt19937 rng(options.seed);
  std::vector<Draw> out;
  for (const auto& robot : spec.robots) {
    const RobotLimits& limits = robot.model->limits();
    for (int k = 0; k < options.draws; ++k) {
      std::vector<double> q(robot.model->num_joints());
      for (size_t j = 0; j < q.size(); ++j) {
        const bool limited = j < limits.joint_min_rad.size();
        std::uniform_real_distribution<double> u(limited ? limits.joint_min_rad[j] : -M_PI,
                                                 limited ? limits.joint_max_rad[j] : M_PI);
        q[j] = u(rng);
      }
      Draw draw = Predict(robot, at, seen, std::move(q));
      if (!draw.observations.empty()) out.push_back(std::move(draw));
    }
  }
  return out;
}

// `recording` with every draw appended as a sample of a pose of its own; `pose_of_draw` the
// pose id each got. Facts a draw cannot know (payload, time, temperature) are the last sample's.
Recording WithDraws(const Recording& recording, std::vector<Draw>& draws,
                    std::vector<int>* pose_of_draw) {
  Recording out = recording;
  int next_id = 0, next_pose = 0;
  for (const auto& s : recording.samples) {
    next_id = std::max(next_id, s.id + 1);
    next_pose = std::max(next_pose, s.pose + 1);
  }
  const Sample last = recording.samples.back();
  for (auto& draw : draws) {
    Sample s = last;
    s.id = next_id++;
    s.pose = next_pose++;
    s.robot = draw.pose.robot;
    s.q = draw.pose.q;
    s.line = 0;
    out.samples.push_back(s);
    pose_of_draw->push_back(s.pose);
    for (Observation obs : draw.observations) {
      obs.sample = s.id;
      obs.line = 0;
      out.observations.push_back(obs);
    }
  }
  return out;
}

// The whitened Jacobian at the answer over recorded and drawn poses, split by pose and by
// parameter group: the geometry (every free parameter of the job) and each candidate.
struct Jacobian {
  Eigen::MatrixXd J;          // rows: residual rows; columns: free parameters
  std::vector<int> row_pose;  // pose id of each row (-1: a prior, always in)
  std::vector<int> geometry;  // columns
  std::vector<std::vector<int>> candidate;
  std::vector<std::string> names, units;  // of the geometry columns
};

Jacobian Linearized(const WorkcellProblem& spec, const Recording& recording,
                    const WorkcellResult& fitted, const std::vector<CandidateEffect>& candidates) {
  WorkcellProblem all = spec;
  for (const auto& c : candidates) all.effects.push_back(c.effect);
  const WorkcellData data = PrepareWorkcellData(all, recording);
  const auto assembled = AssembleWorkcell(all, recording, data, fitted.noise, fitted.estimate);
  // What the identification held (a parametrisation's conventions, what the recorded poses
  // cannot see) stays held: free, its null direction would put every sigma at infinity.
  HoldParameters(&assembled->problem, HeldOf(fitted.unidentifiable));
  const Linearization at = Linearize(assembled->problem);
  if (!at.valid) {
    throw InputError({}, "the model cannot be evaluated at some planned poses",
                     "Narrow the joint limits in the robot config to what the arm can reach");
  }
  Jacobian out;
  out.J = Eigen::MatrixXd(at.jacobian);
  std::map<int, int> candidate_of_block;
  for (size_t i = 0; i < candidates.size(); ++i) {
    candidate_of_block[assembled->effect_block[spec.effects.size() + i]] = static_cast<int>(i);
  }
  out.candidate.resize(candidates.size());
  const Problem& problem = assembled->problem;
  for (int c = 0; c < problem.num_free(); ++c) {
    const auto& f = problem.free_parameters()[c];
    const auto it = candidate_of_block.find(f.block);
    if (it != candidate_of_block.end()) {
      out.candidate[it->second].push_back(c);
      continue;
    }
    out.geometry.push_back(c);
    out.names.push_back(f.name);
    out.units.push_back(f.unit);
  }
  const auto& first = problem.residual_rows();
  out.row_pose.assign(out.J.rows(), -1);
  for (size_t b = 0; b < first.size(); ++b) {
    const int end = b + 1 < first.size() ? first[b + 1] : static_cast<int>(out.J.rows());
    const MeasurementLabel* label = assembled->LabelOf(b);
    const int pose = label ? label->pose : -1;
    for (int r = first[b]; r < end; ++r) out.row_pose[r] = pose;
  }
  return out;
}

Eigen::MatrixXd Rows(const Eigen::MatrixXd& J, const std::vector<int>& rows,
                     const std::vector<int>& columns) {
  Eigen::MatrixXd out(rows.size(), columns.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < columns.size(); ++j) out(i, j) = J(rows[i], columns[j]);
  }
  return out;
}

// A set of rows with an orthonormal basis of the geometry's columns over them: what every
// candidate's signature is projected against. Made once per row set (its QR is the plan's
// largest cost: a real recording has tens of thousands of rows), not once per candidate.
struct RowSpan {
  RowSpan(const Jacobian& jac, std::vector<int> rows_in)
      : rows(std::move(rows_in)), geometry(OrthonormalBasis(Rows(jac.J, rows, jac.geometry))) {}
  std::vector<int> rows;
  Eigen::MatrixXd geometry;
};

// Share of a candidate's signature (its columns over the span's rows) outside the geometry's
// span.
double Unabsorbed(const Jacobian& jac, const RowSpan& span, const std::vector<int>& candidate) {
  const Eigen::MatrixXd Jc = Rows(jac.J, span.rows, candidate);
  if (Jc.norm() == 0.0) return 0.0;
  return ProjectOut(span.geometry, Jc).norm() / Jc.norm();
}

// An orthonormal basis of what the geometry leaves of a candidate's signature over the span's
// rows.
Eigen::MatrixXd UnabsorbedBasis(const Jacobian& jac, const RowSpan& span,
                                const std::vector<int>& candidate) {
  return OrthonormalBasis(ProjectOut(span.geometry, Rows(jac.J, span.rows, candidate)));
}

// Each of `columns`' parameters' sigma at the floor from `rows`, fitted together (1e150 where
// undetermined: the pseudo-inverse of a zero singular value).
Eigen::VectorXd SigmaAtFloor(const Jacobian& jac, const std::vector<int>& rows,
                             const std::vector<int>& columns) {
  const Eigen::MatrixXd G = Rows(jac.J, rows, columns);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd variance = Eigen::VectorXd::Zero(G.cols());
  for (Eigen::Index k = 0; k < s.size(); ++k) {
    const Eigen::VectorXd v = svd.matrixV().col(k);
    variance += v.cwiseAbs2() / std::max(s[k] * s[k], 1e-300);
  }
  return variance.cwiseSqrt();
}

// Greedy D-optimal choice of `count` draws (indices), given the recorded rows.
std::vector<int> ChooseDOptimal(const Jacobian& jac, const std::vector<int>& recorded_rows,
                                const std::vector<std::vector<int>>& draw_rows,
                                const std::vector<int>& columns, int count) {
  // Columns scaled to unit norm over every row (the determinant's ratios do not change; its
  // conditioning does).
  const Eigen::MatrixXd recorded = Rows(jac.J, recorded_rows, columns);
  std::vector<Eigen::MatrixXd> blocks;
  Eigen::VectorXd norms = recorded.colwise().squaredNorm().transpose();
  for (const auto& rows : draw_rows) {
    blocks.push_back(Rows(jac.J, rows, columns));
    norms += blocks.back().colwise().squaredNorm().transpose();
  }
  const Eigen::MatrixXd scale = norms.cwiseSqrt().cwiseMax(1e-300).cwiseInverse().asDiagonal();
  for (auto& block : blocks) block *= scale;
  Eigen::MatrixXd M = (recorded * scale).transpose() * (recorded * scale);
  M += 1e-9 * std::max(1e-300, M.trace() / M.rows()) *
       Eigen::MatrixXd::Identity(M.rows(), M.cols());  // finite where nothing is determined yet
  std::vector<int> chosen;
  std::vector<bool> taken(blocks.size(), false);
  for (int step = 0; step < count; ++step) {
    const Eigen::LDLT<Eigen::MatrixXd> inverse(M);
    int best = -1;
    double best_gain = -INFINITY;
    for (size_t k = 0; k < blocks.size(); ++k) {
      if (taken[k]) continue;
      const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(blocks[k].rows(), blocks[k].rows()) +
                                blocks[k] * inverse.solve(blocks[k].transpose());
      const double gain = Eigen::LDLT<Eigen::MatrixXd>(S).vectorD().array().log().sum();
      if (gain > best_gain) best_gain = gain, best = static_cast<int>(k);
    }
    if (best < 0) break;
    taken[best] = true;
    chosen.push_back(best);
    M += blocks[best].transpose() * blocks[best];
  }
  return chosen;
}

// The candidates to plan for: those named, or every one the recorded poses leave untestable
// by absorption that the drawn poses could make testable.
std::vector<int> Targets(const Jacobian& jac, const std::vector<CandidateEffect>& candidates,
                         const RowSpan& recorded, const std::vector<int>& draw_rows,
                         const PosePlanOptions& options) {
  std::vector<int> every_row = recorded.rows;
  every_row.insert(every_row.end(), draw_rows.begin(), draw_rows.end());
  const RowSpan every(jac, std::move(every_row));
  std::vector<int> out;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const auto& named = options.effects;
    if (!named.empty()) {
      if (std::find(named.begin(), named.end(), candidates[c].effect.name) != named.end()) {
        out.push_back(static_cast<int>(c));
      }
      continue;
    }
    if (Rows(jac.J, draw_rows, jac.candidate[c]).norm() == 0.0) continue;  // never acts
    // Absorbed by the free frames whatever the pose (a constant tilt of a board's estimates is
    // its carrier's rotation): no plan helps.
    if (Unabsorbed(jac, every, jac.candidate[c]) < options.min_unabsorbed) continue;
    if (Unabsorbed(jac, recorded, jac.candidate[c]) < options.min_unabsorbed) {
      out.push_back(static_cast<int>(c));
    }
  }
  return out;
}

// What the plan predicts for one candidate: the share of its signature the geometry leaves,
// and its parameters' sigma at the floor when fitted with the geometry (the finder's refit: an
// absorbed candidate's sigma is the geometry's near-singular direction, large), before and after.
PlannedEffect PlannedFor(const Jacobian& jac, const CandidateEffect& candidate,
                         const std::vector<int>& own, const RowSpan& before_rows,
                         const RowSpan& after_rows) {
  PlannedEffect e{candidate.effect.name,
                  candidate.label,
                  Unabsorbed(jac, before_rows, own),
                  Unabsorbed(jac, after_rows, own),
                  {}};
  std::vector<int> columns = jac.geometry;
  columns.insert(columns.end(), own.begin(), own.end());
  const Eigen::VectorXd before = SigmaAtFloor(jac, before_rows.rows, columns);
  const Eigen::VectorXd after = SigmaAtFloor(jac, after_rows.rows, columns);
  const std::vector<Parameter>& parameters = candidate.effect.effect->parameters();
  for (size_t i = 0; i < own.size() && i < parameters.size(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(jac.geometry.size() + i);
    e.sigma.push_back({candidate.effect.name + "." + parameters[i].name, parameters[i].unit,
                       before[k], after[k]});
  }
  return e;
}

// What the plan predicts for two named candidates: how alike the poses leave them, and their
// parameters' sigma at the floor fitted together with the geometry, before and after.
PlannedPair PlannedTogether(const Jacobian& jac, const CandidateEffect& a,
                            const std::vector<int>& a_columns, const CandidateEffect& b,
                            const std::vector<int>& b_columns, const RowSpan& before_rows,
                            const RowSpan& after_rows) {
  PlannedPair pair{a.label,
                   b.label,
                   CanonicalCorrelation(UnabsorbedBasis(jac, before_rows, a_columns),
                                        UnabsorbedBasis(jac, before_rows, b_columns)),
                   CanonicalCorrelation(UnabsorbedBasis(jac, after_rows, a_columns),
                                        UnabsorbedBasis(jac, after_rows, b_columns)),
                   {}};
  std::vector<int> columns = jac.geometry;
  columns.insert(columns.end(), a_columns.begin(), a_columns.end());
  columns.insert(columns.end(), b_columns.begin(), b_columns.end());
  const Eigen::VectorXd before = SigmaAtFloor(jac, before_rows.rows, columns);
  const Eigen::VectorXd after = SigmaAtFloor(jac, after_rows.rows, columns);
  Eigen::Index k = static_cast<Eigen::Index>(jac.geometry.size());
  const std::pair<const CandidateEffect*, const std::vector<int>*> members[] = {{&a, &a_columns},
                                                                                {&b, &b_columns}};
  for (const auto& [c, c_columns] : members) {
    const std::vector<Parameter>& parameters = c->effect.effect->parameters();
    for (size_t i = 0; i < c_columns->size() && i < parameters.size(); ++i, ++k) {
      pair.sigma.push_back(
          {c->effect.name + "." + parameters[i].name, parameters[i].unit, before[k], after[k]});
    }
  }
  return pair;
}

}  // namespace

// A name no candidate has would plan for nothing and say so nowhere (exit 0).
void CheckNamedEffects(const std::vector<CandidateEffect>& candidates,
                       const PosePlanOptions& options) {
  std::string known;
  for (const auto& c : candidates) known += (known.empty() ? "" : ", ") + c.effect.name;
  for (const std::string& name : options.effects) {
    const bool found = std::any_of(candidates.begin(), candidates.end(),
                                   [&](const CandidateEffect& c) { return c.effect.name == name; });
    if (!found) {
      throw InputError({"--effect", 0, 0}, "no candidate effect '" + name + "'",
                       "Name one of: " + known);
    }
  }
}

PosePlan PlanPoses(const WorkcellProblem& spec, const Recording& recording,
                   const WorkcellResult& fitted, const std::vector<CandidateEffect>& candidates,
                   const PosePlanOptions& options) {
  CheckNamedEffects(candidates, options);
  PosePlan plan;
  plan.draws = options.draws;
  plan.min_unabsorbed = options.min_unabsorbed;
  std::vector<Draw> draws = DrawInView(spec, recording, fitted.estimate, options);
  plan.draws_in_view = static_cast<int>(draws.size());
  if (draws.empty()) {
    throw InputError({recording.folder, 0, 0},
                     "no drawn pose inside the joint limits puts a target where a camera has seen "
                     "one",
                     "Check the robot config's joint limits and the job's cameras");
  }
  std::vector<int> pose_of_draw;
  const Recording extended = WithDraws(recording, draws, &pose_of_draw);
  const Jacobian jac = Linearized(spec, extended, fitted, candidates);
  std::map<int, int> draw_of_pose;
  for (size_t k = 0; k < pose_of_draw.size(); ++k) {
    draw_of_pose[pose_of_draw[k]] = static_cast<int>(k);
  }
  std::vector<int> recorded_rows, all_draw_rows;
  std::vector<std::vector<int>> draw_rows(draws.size());
  for (int r = 0; r < static_cast<int>(jac.row_pose.size()); ++r) {
    const auto it = draw_of_pose.find(jac.row_pose[r]);
    if (it == draw_of_pose.end()) {
      recorded_rows.push_back(r);
    } else {
      draw_rows[it->second].push_back(r);
      all_draw_rows.push_back(r);
    }
  }
  const RowSpan recorded(jac, recorded_rows);
  const std::vector<int> targets = Targets(jac, candidates, recorded, all_draw_rows, options);
  std::vector<int> columns = jac.geometry;
  for (int c : targets) {
    columns.insert(columns.end(), jac.candidate[c].begin(), jac.candidate[c].end());
  }
  const std::vector<int> chosen =
      ChooseDOptimal(jac, recorded_rows, draw_rows, columns, options.poses);
  std::vector<int> after_rows = recorded_rows;
  for (int k : chosen) {
    plan.poses.push_back(draws[k].pose);
    after_rows.insert(after_rows.end(), draw_rows[k].begin(), draw_rows[k].end());
  }
  const RowSpan after(jac, after_rows);
  for (int c : targets) {
    plan.effects.push_back(PlannedFor(jac, candidates[c], jac.candidate[c], recorded, after));
  }
  for (size_t i = 0; i < targets.size() && !options.effects.empty(); ++i) {
    for (size_t k = i + 1; k < targets.size(); ++k) {
      plan.pairs.push_back(PlannedTogether(jac, candidates[targets[i]], jac.candidate[targets[i]],
                                           candidates[targets[k]], jac.candidate[targets[k]],
                                           recorded, after));
    }
  }
  const Eigen::VectorXd sigma_before = SigmaAtFloor(jac, recorded_rows, jac.geometry);
  const Eigen::VectorXd sigma_after = SigmaAtFloor(jac, after_rows, jac.geometry);
  for (size_t i = 0; i < jac.geometry.size(); ++i) {
    plan.sigma.push_back({jac.names[i], jac.units[i], sigma_before[i], sigma_after[i]});
  }
  return plan;
}

bool PlanMeetsItsGoal(const PosePlan& plan, std::vector<std::string>* unmet) {
  std::vector<std::string> lines;
  for (const auto& e : plan.effects) {
    if (e.unabsorbed_after < plan.min_unabsorbed) lines.push_back(e.label + " stays untestable");
  }
  for (const auto& p : plan.pairs) {
    char line[256];
    if (p.correlation_after >= p.correlation_before) {
      std::snprintf(line, sizeof(line), "%s and %s are left as alike or more (%.2f -> %.2f)",
                    p.a.c_str(), p.b.c_str(), p.correlation_before, p.correlation_after);
      lines.push_back(line);
    } else if (p.correlation_after >= 0.99) {
      std::snprintf(line, sizeof(line), "%s and %s stay one finding (alike %.2f)", p.a.c_str(),
                    p.b.c_str(), p.correlation_after);
      lines.push_back(line);
    }
  }
  if (unmet != nullptr) *unmet = lines;
  return lines.empty();
}

std::string PosePlanReport(const PosePlan& plan) {
  std::ostringstream out;
  out << "Planned " << plan.poses.size() << " poses (D-optimal among " << plan.draws_in_view
      << " of " << plan.draws
      << " poses drawn inside the robot config's joint limits, each target where a camera "
         "that saw it before sees it again).\n";
  std::vector<std::string> unmet;
  if (PlanMeetsItsGoal(plan, &unmet)) {
    out << "Goal met: "
        << (plan.effects.empty() ? "the recorded poses leave no candidate untestable"
            : plan.pairs.empty() ? "every planned effect testable"
                                 : "every named effect testable and each pair told further "
                                   "apart")
        << ".\n";
  } else {
    out << "Goal not met by the best " << plan.poses.size() << " poses found among those drawn:\n";
    for (const auto& line : unmet) out << "  - " << line << "\n";
    if (!plan.pairs.empty()) {
      out << "  Poses alone may not tell them apart: record under a condition the poses do not "
             "set (temperature, load, time), or plan more poses (-n).\n";
    }
  }
  for (const auto& e : plan.effects) {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "  %s: %.0f %% of its signature outside the geometry -> %.0f %%%s\n",
                  e.label.c_str(), 100 * e.unabsorbed_before, 100 * e.unabsorbed_after,
                  e.unabsorbed_after >= 0.05 ? " (testable)" : " (still untestable)");
    out << line;
    for (const auto& p : e.sigma) {
      std::snprintf(line, sizeof(line), "    %s: sigma %.2g -> %.2g %s\n", p.name.c_str(), p.before,
                    p.after, p.unit.c_str());
      out << line;
    }
  }
  for (const auto& p : plan.pairs) {
    char line[512];
    std::snprintf(line, sizeof(line),
                  "  %s and %s: alike %.2f -> %.2f (canonical correlation of what the geometry "
                  "leaves of them; the finder calls 0.99 one finding)\n",
                  p.a.c_str(), p.b.c_str(), p.correlation_before, p.correlation_after);
    out << line;
    for (const auto& s : p.sigma) {
      std::snprintf(line, sizeof(line), "    %s fitted with the other: sigma %.2g -> %.2g %s\n",
                    s.name.c_str(), s.before, s.after, s.unit.c_str());
      out << line;
    }
  }
  out << "  predicted sigma at the floor, before -> after:\n";
  for (const auto& s : plan.sigma) {
    char line[256];
    std::snprintf(line, sizeof(line), "    %s: %.2g -> %.2g %s\n", s.name.c_str(), s.before,
                  s.after, s.unit.c_str());
    out << line;
  }
  return out.str();
}

std::string PosePlanCsv(const PosePlan& plan) {
  std::ostringstream out;
  size_t joints = 0;
  for (const auto& p : plan.poses) joints = std::max(joints, p.q.size());
  out << "robot";
  for (size_t j = 1; j <= joints; ++j) out << ",q" << j;
  out << ",cameras\n";
  out.precision(10);
  for (const auto& p : plan.poses) {
    out << p.robot;
    for (double q : p.q) out << "," << q;
    std::string cameras;
    for (const auto& c : p.cameras) cameras += (cameras.empty() ? "" : " ") + c;
    out << "," << cameras << "\n";
  }
  return out.str();
}

}  // namespace cellmetry

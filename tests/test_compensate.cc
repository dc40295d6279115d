// `cellmetry compensate` (core/compensation): commands computed from a fitted result, pushed
// through the TRUE simulated robot (truth geometry and the physics concealed in the recording),
// reach their targets within the calibration's own uncertainty; the nominal kinematics' commands
// miss by many sigma. A UR3 whose joint 3 gives under its payload, a delta arm whose motor 3 has
// backlash; refusals in words; the Jacobian against central differences.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "cellmetry/cell/result_io.h"
#include "cellmetry/compensation/compensation.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

// A simulated cell with concealed physics, fitted by a job that models it (its values come from
// the fit), the result written and read back as `cellmetry compensate` reads it.
struct FittedCell {
  WorkcellSimulationSpec truth;
  std::string result_folder;
  CalibratedCell calibrated;
  CompensationChain chain;
  double noise_floor_mm = 0.0;  // the recording's per-capture noise, 3D RMS
};

std::string Sim(const std::string& dir, const std::string& name, const std::string& robot_line,
                const std::string& model_errors) {
  std::string sim = testing::ReadText(testing::Source("configs/simulations/" + name));
  const std::string config = name.rfind("ur3", 0) == 0 ? "ur3_vsb2020.yaml" : "delta.yaml";
  sim =
      testing::ReplaceOnce(sim, "../robots/" + config, testing::Source("configs/robots/" + config));
  sim = testing::ReplaceOnce(sim, "random: 150", "random: 80");
  sim = testing::ReplaceOnce(sim, robot_line,
                             robot_line + "    model_errors: " + model_errors + "\n");
  testing::WriteText(dir + "/sim.yaml", sim);
  return dir + "/sim.yaml";
}

FittedCell Fit(const std::string& dir, WorkcellSimulationSpec truth, const std::string& job_name,
               const std::string& config, const std::string& robot_additions) {
  FittedCell cell;
  cell.truth = truth;
  const Recording recording = SimulateWorkcell(truth, nullptr);
  std::string job = testing::ReadText(testing::Source("configs/jobs/" + job_name));
  job = testing::ReplaceOnce(job, "model: ../robots/" + config,
                             "model: " + testing::Source("configs/robots/" + config));
  job = job.substr(0, job.find("diagnosis:"));
  job = testing::ReplaceOnce(job, "noise:\n", robot_additions + "noise:\n");
  testing::WriteText(dir + "/job.yaml", job);
  const WorkcellJob loaded = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), false);
  cell.result_folder = dir + "/fit";
  WriteWorkcellResult(testing::Identify(loaded, recording), cell.result_folder);
  cell.calibrated = ReadCalibratedCell(cell.result_folder, testing::Plugins());
  cell.chain = ChainFromResult(cell.calibrated, "", "");
  cell.noise_floor_mm = truth.sigma_position_mm.norm();
  return cell;
}

// UR3 of the physics suite off its nominal table (joint offsets, link lengths: what a real arm's
// are), joint 3 giving under the load (test_support's concealed compliance); the job frees those
// parameters and models joint 3's compliance.
const FittedCell& Ur3Cell() {
  static const FittedCell cell = [] {
    const std::string dir = testing::TempDir("compensate/ur3_cell");
    const std::string sim = Sim(dir, "ur3_physics_base.yaml",
                                "    base: {xyz: [431, 555, -460], rvec: [0.002, -0.001, 0.003]}\n",
                                "{j2.offset: 0.002, j3.offset: -0.0015, j4.offset: 0.001, "
                                "j3.a: 0.4, j4.a: -0.3, j3.beta: 0.0008}");
    WorkcellSimulationSpec spec = LoadWorkcellSimulation(sim, testing::Plugins());
    testing::ConcealJoint3Compliance(&spec);
    return Fit(dir, spec, "ur3_diagnose.yaml", "ur3_vsb2020.yaml",
               "    free_model: [j2.offset, j3.offset, j4.offset, j3.a, j4.a, j3.beta]\n"
               "    effects:\n"
               "      - {type: joint_compliance, joints: [3], "
               "link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}\n");
  }();
  return cell;
}

// The physics suite's delta arm off its nominal geometry, motor 3 with 3 mrad of backlash; the
// job fits the whole geometry and models motor 3's backlash.
const FittedCell& DeltaCell() {
  static const FittedCell cell = [] {
    const std::string dir = testing::TempDir("compensate/delta_cell");
    const std::string sim = Sim(dir, "delta_physics_base.yaml",
                                "    base: {xyz: [0, 0, 800], rvec: [0.002, -0.001, 0.003]}\n",
                                "{arm1.homing: 0.004, arm2.L: 0.5, arm3.l: -0.6, arm2.R: 0.3}");
    WorkcellSimulationSpec spec = LoadWorkcellSimulation(sim, testing::Plugins());
    SimulatedEffect backlash;
    backlash.name = "delta.backlash";
    backlash.effect = testing::Plugins().CreateEffect(
        "backlash", ConfigNode::LoadString("{type: backlash, joints: [3]}", "test"),
        *spec.robots[0].model);
    backlash.values = {0.003};
    spec.robots[0].effects.push_back(backlash);
    return Fit(dir, spec, "delta_diagnose.yaml", "delta.yaml",
               "    effects:\n      - {type: backlash, joints: [3]}\n");
  }();
  return cell;
}

// Where the true robot puts the tool for each command, in the world: the simulator itself
// (truth geometry, concealed physics, the commands in this order for the approach directions),
// noise-free, read back through the true first camera.
std::vector<Pose> TrueToolPoses(const FittedCell& cell, const std::vector<std::vector<double>>& q,
                                const std::vector<double>& payloads_kg) {
  WorkcellSimulationSpec spec = cell.truth;
  spec.sigma_position_mm.setZero();
  spec.sigma_rotation_rad.setZero();
  spec.repeats = 1;
  for (auto& [name, camera] : spec.cameras) camera.in_view_only = false;  // read every pose
  SimulatedRobot& robot = spec.robots.front();
  robot.pose_set.reset();
  robot.joint_poses = q;
  robot.payloads_kg = payloads_kg;
  const Recording recording = SimulateWorkcell(spec, nullptr);
  EXPECT_EQ(recording.samples.size(), q.size()) << "a command the true robot cannot reach";
  const std::string camera = spec.T_world_cam.begin()->first;
  std::vector<Pose> poses(q.size());
  for (const auto& o : recording.observations) {
    if (o.camera != camera || o.target != "tool") continue;
    poses.at(o.sample) = spec.T_world_cam.at(camera) * PoseFromRvecT(*o.rvec, o.position_mm);
  }
  return poses;
}

// Targets the arm reaches: where the nominal chain puts the tool at random joints in `lower` ..
// `upper`, each once per payload of `payloads_kg` in a row, written to TARGETS.csv (poses with
// seeds for a six-joint arm, positions for a delta) and read back.
std::vector<CompensationTarget> MakeTargets(const FittedCell& cell, const std::string& path,
                                            const std::vector<double>& lower,
                                            const std::vector<double>& upper,
                                            const std::vector<double>& payloads_kg, int poses) {
  const CompensationChain nominal = NominalChain(cell.chain);
  const int n = static_cast<int>(lower.size());
  const bool pose = n >= 6;
  std::mt19937 rng(5);
  std::string csv = "id,x_mm,y_mm,z_mm";
  csv += pose ? ",rx_rad,ry_rad,rz_rad" : "";
  for (int j = 1; pose && j <= n; ++j) csv += ",q" + std::to_string(j) + "_rad";
  csv += ",payload_kg\n";
  for (int k = 0; k < poses; ++k) {
    std::vector<double> q(n);
    for (int j = 0; j < n; ++j) q[j] = std::uniform_real_distribution<>(lower[j], upper[j])(rng);
    Pose T;
    EXPECT_TRUE(ToolPose(nominal, q, {}, &T));
    std::vector<double> cells = {T.t.x(), T.t.y(), T.t.z()};
    if (pose) {
      const Eigen::Vector3d r = RvecFromRotation(T.R);
      cells.insert(cells.end(), {r.x(), r.y(), r.z()});
      // The seed: a few hundredths of a radian off the answer, as a taught pose would be.
      for (double v : q) cells.push_back(v + 0.03);
    }
    for (double payload : payloads_kg) {
      csv += "p" + std::to_string(k) + "_" + std::to_string(static_cast<int>(payload));
      for (double v : cells) {
        char text[32];
        std::snprintf(text, sizeof text, ",%.17g", v);
        csv += text;
      }
      csv += "," + std::to_string(payload) + "\n";
    }
  }
  testing::WriteText(path, csv);
  return ReadCompensationTargets(path, n);
}

// Position errors of `reached` against the targets, mm.
std::vector<double> PositionErrors(const std::vector<CompensationTarget>& targets,
                                   const std::vector<Pose>& reached) {
  std::vector<double> errors;
  for (size_t k = 0; k < targets.size(); ++k) {
    errors.push_back((reached[k].t - targets[k].p_world_tool_mm).norm());
  }
  return errors;
}

double Rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / values.size());
}

// The commands `chain` gives for the targets, each solved from the compensated one: with the
// nominal chain, what a controller that knows only the nominal kinematics would send; with the
// calibrated geometry and no effects, what the effects add.
std::vector<std::vector<double>> CommandsOn(const CompensationChain& chain,
                                            const std::vector<CompensationTarget>& targets,
                                            const std::vector<CompensatedCommand>& commands) {
  std::vector<std::vector<double>> q;
  for (size_t k = 0; k < targets.size(); ++k) {
    const CompensationTarget& t = targets[k];
    const bool pose = t.kind == CompensationTarget::Kind::kPose;
    const Eigen::Matrix3d* R = pose ? &t.R_world_tool : nullptr;
    const SolvedCommand solved =
        SolveCommand(chain, t.p_world_tool_mm, R, commands[k].q_rad, {}, CompensationOptions{});
    EXPECT_TRUE(solved.reached) << solved.failure;
    q.push_back(solved.q_rad);
  }
  return q;
}

CompensationChain GeometryOnly(const CompensationChain& chain) {
  CompensationChain geometry = chain;
  geometry.effects.clear();
  geometry.effect_values.clear();
  geometry.effect_names.clear();
  return geometry;
}

std::vector<double> Payloads(const std::vector<CompensationTarget>& targets) {
  std::vector<double> payloads;
  for (const auto& t : targets) payloads.push_back(t.payload_kg);
  return payloads;
}

struct Outcome {
  double compensated_rms_mm, geometry_only_rms_mm, nominal_rms_mm, mean_sigma_mm;
  double worst_in_sigma;  // max over targets of compensated error / its sigma
  // RMS over targets given twice (first and last payload) of the distance between where the
  // true robot put the tool the two times: the payload's sag, free of the calibration's error.
  double compensated_sag_mm, geometry_only_sag_mm;
};

// The sag between consecutive runs of `per_pose` targets (one pose, each payload).
double Sag(const std::vector<Pose>& reached, int per_pose) {
  std::vector<double> sag;
  for (size_t k = 0; k + per_pose - 1 < reached.size(); k += per_pose) {
    sag.push_back((reached[k + per_pose - 1].t - reached[k].t).norm());
  }
  return Rms(sag);
}

Outcome Measure(const FittedCell& cell, const std::vector<CompensationTarget>& targets,
                int per_pose) {
  const auto commands =
      Compensate(cell.chain, targets, cell.calibrated.covariance, CompensationOptions{});
  std::vector<std::vector<double>> q;
  Outcome out{};
  for (const auto& c : commands) {
    EXPECT_FALSE(c.refused) << c.target->id << ": " << c.reason;
    EXPECT_LT(c.error_mm, 1e-6);
    EXPECT_TRUE(c.sigma_mm.has_value());
    q.push_back(c.q_rad);
    out.mean_sigma_mm += c.sigma_mm.value_or(NAN) / commands.size();
  }
  const auto payloads = Payloads(targets);
  const auto reached = TrueToolPoses(cell, q, payloads);
  const auto compensated = PositionErrors(targets, reached);
  for (size_t k = 0; k < commands.size(); ++k) {
    out.worst_in_sigma = std::max(out.worst_in_sigma, compensated[k] / *commands[k].sigma_mm);
  }
  out.compensated_rms_mm = Rms(compensated);
  out.compensated_sag_mm = Sag(reached, per_pose);
  const auto geometry_only =
      TrueToolPoses(cell, CommandsOn(GeometryOnly(cell.chain), targets, commands), payloads);
  out.geometry_only_rms_mm = Rms(PositionErrors(targets, geometry_only));
  out.geometry_only_sag_mm = Sag(geometry_only, per_pose);
  out.nominal_rms_mm = Rms(PositionErrors(
      targets,
      TrueToolPoses(cell, CommandsOn(NominalChain(cell.chain), targets, commands), payloads)));
  std::printf(
      "compensated %.4f mm (worst %.2f sigma), geometry only %.4f mm, nominal %.4f mm, "
      "mean sigma %.4f mm, noise floor %.3f mm; payload sag compensated %.4f mm, "
      "geometry only %.4f mm\n",
      out.compensated_rms_mm, out.worst_in_sigma, out.geometry_only_rms_mm, out.nominal_rms_mm,
      out.mean_sigma_mm, cell.noise_floor_mm, out.compensated_sag_mm, out.geometry_only_sag_mm);
  return out;
}

TEST(Compensate, Ur3CommandsReachTheirTargetsUnderConcealedComplianceAndGeometry) {
  const FittedCell& cell = Ur3Cell();
  ASSERT_EQ(cell.chain.effects.size(), 1u);
  const std::string dir = testing::TempDirForThisTest("compensate");
  // Shoulder and elbow away from their singular stretch; each pose empty and with the UR3's
  // full 3 kg.
  const auto targets = MakeTargets(cell, dir + "/targets.csv", {-3, 2.6, -2.0, -3, 0.5, -3},
                                   {3, 4.0, -0.4, 3, 2.6, 3}, {0, 3}, 12);
  const Outcome o = Measure(cell, targets, 2);
  // With compensation: within the calibration's own uncertainty, below one capture's noise.
  EXPECT_LT(o.worst_in_sigma, 4.0);
  EXPECT_LT(o.compensated_rms_mm, 0.5 * cell.noise_floor_mm);
  // Without: the nominal kinematics misses by many sigma.
  EXPECT_GT(o.nominal_rms_mm, 8 * o.mean_sigma_mm);
  EXPECT_GT(o.nominal_rms_mm, 3 * cell.noise_floor_mm);
  // The compliance: with the geometry alone the tool sags under the payload; compensated, it
  // stays where it was without (what remains is the fitted compliance's error).
  EXPECT_GT(o.geometry_only_sag_mm, 4 * o.compensated_sag_mm);
}

TEST(Compensate, DeltaCommandsReachTheirTargetsUnderConcealedBacklashAndGeometry) {
  const FittedCell& cell = DeltaCell();
  ASSERT_EQ(cell.chain.effects.size(), 1u);
  const std::string dir = testing::TempDirForThisTest("compensate");
  // Positions in random order: every motor comes at them from either side.
  const auto targets =
      MakeTargets(cell, dir + "/targets.csv", {-0.3, -0.3, -0.3}, {1.1, 1.1, 1.1}, {0}, 24);
  const Outcome o = Measure(cell, targets, 1);
  EXPECT_LT(o.worst_in_sigma, 4.0);
  EXPECT_LT(o.compensated_rms_mm, 0.5 * cell.noise_floor_mm);
  EXPECT_GT(o.nominal_rms_mm, 8 * o.mean_sigma_mm);
  EXPECT_GT(o.nominal_rms_mm, 3 * cell.noise_floor_mm);
  // The backlash: the geometry alone misses by half the play times the arm, both ways.
  EXPECT_GT(o.geometry_only_rms_mm, 5 * o.compensated_rms_mm);
}

// A chain built in memory: `config`'s robot at its nominal values with `effects` (YAML blocks)
// at `values`, placed and tooled as in the physics suite.
CompensationChain MemoryChain(const std::string& config, const std::vector<std::string>& effects,
                              const std::vector<std::vector<double>>& values) {
  CompensationChain chain;
  chain.robot = config == "ur3_vsb2020.yaml" ? "ur3" : "delta";
  chain.tool = "tool";
  chain.model = testing::Plugins().CreateRobotModel(
      config == "ur3_vsb2020.yaml" ? "serial_mdh" : "delta",
      ConfigNode::LoadFile(testing::Source("configs/robots/" + config)));
  for (const auto& p : chain.model->parameters()) chain.nominal_params.push_back(p.nominal);
  chain.params = chain.nominal_params;
  for (size_t k = 0; k < effects.size(); ++k) {
    const ConfigNode node = ConfigNode::LoadString(effects[k], "test");
    chain.effects.push_back(
        testing::Plugins().CreateEffect(node["type"].AsString(), node, *chain.model));
    chain.effect_names.push_back(chain.robot + ".effect" + std::to_string(k));
    chain.effect_values.push_back(values[k]);
  }
  const Eigen::Vector3d rb(0.002, -0.001, 0.003), rt(0.001, 0.002, -0.001);
  chain.T_world_base = PoseFromRvecT(rb, Eigen::Vector3d(431, 555, -460));
  chain.T_flange_tool = PoseFromRvecT(rt, Eigen::Vector3d(0.5, -0.3, 66));
  return chain;
}

// d T_world_tool / d q by central differences: position, then the rotation about the world's
// axes (Log(R(q + h) R(q - h)^T) / 2h).
Eigen::Matrix<double, 6, Eigen::Dynamic> CentralDifferences(const CompensationChain& chain,
                                                            const std::vector<double>& q,
                                                            const CommandContext& context) {
  constexpr double h = 1e-6;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, q.size());
  for (size_t j = 0; j < q.size(); ++j) {
    std::vector<double> up = q, down = q;
    up[j] += h;
    down[j] -= h;
    Pose a, b;
    EXPECT_TRUE(ToolPose(chain, up, context, &a) && ToolPose(chain, down, context, &b));
    J.col(j) << (a.t - b.t) / (2 * h), RotationError(a.R, b.R) / (2 * h);
  }
  return J;
}

// Largest difference between the Jacobian and central differences, relative to its largest
// entry, over a few commands.
double JacobianMismatch(const CompensationChain& chain, const std::vector<double>& lower,
                        const std::vector<double>& upper, const CommandContext& context) {
  std::mt19937 rng(3);
  double worst = 0.0;
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<double> q(lower.size());
    for (size_t j = 0; j < q.size(); ++j) {
      q[j] = std::uniform_real_distribution<>(lower[j], upper[j])(rng);
    }
    Pose T;
    Eigen::Matrix<double, 6, Eigen::Dynamic> J;
    EXPECT_TRUE(ToolPoseJacobian(chain, q, context, &T, &J));
    const auto numeric = CentralDifferences(chain, q, context);
    worst = std::max(worst, (J - numeric).cwiseAbs().maxCoeff() / J.cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(CompensateJacobian, MatchesCentralDifferencesForEffectsThatDoNotReadTheJoints) {
  const CommandContext context{{1, -1, 1, -1, 1, -1}, 1.0, 30.0, NAN};
  const auto ur3 =
      MemoryChain("ur3_vsb2020.yaml", {"{type: backlash, joints: [2, 3]}", "{type: thermal_drift}"},
                  {{0.002, 0.003}, {1.2e-5}});
  EXPECT_LT(JacobianMismatch(ur3, {-3, 2.6, -2, -3, 0.5, -3}, {3, 4, -0.4, 3, 2.6, 3}, context),
            1e-7);
  const auto delta =
      MemoryChain("delta.yaml", {"{type: backlash, joints: [1, 3]}", "{type: thermal_drift}"},
                  {{0.002, 0.003}, {1.2e-5}});
  EXPECT_LT(JacobianMismatch(delta, {-0.3, -0.3, -0.3}, {1.1, 1.1, 1.1}, context), 1e-7);
}

TEST(CompensateJacobian, LeavesOutOnlyTheComplianceContextShareItDocuments) {
  // Joint 3's compliance reads the gravity torque at q in double: its derivative is held out,
  // a share of the order of the compliance times the torque's rate (compensation_chain.h).
  const CommandContext context{{}, 3.0, NAN, NAN};
  const auto ur3 = MemoryChain("ur3_vsb2020.yaml",
                               {"{type: joint_compliance, joints: [3], "
                                "link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}"},
                               {{4e-5}});
  const double mismatch =
      JacobianMismatch(ur3, {-3, 2.6, -2, -3, 0.5, -3}, {3, 4, -0.4, 3, 2.6, 3}, context);
  std::printf("compliance: Jacobian vs central differences %.2g of its largest entry\n", mismatch);
  EXPECT_GT(mismatch, 1e-7);  // the held-out share is there, and is what is documented
  EXPECT_LT(mismatch, 2e-3);
}

// The derivative ToolPoseCovariance propagates through, parameter by parameter: a covariance
// with only `name` (variance 1) gives G G^T, whose diagonal's roots are |d pose / d name|.
void ExpectPropagatedDerivative(const CompensationChain& chain, const std::vector<double>& q,
                                const std::string& name, const CompensationChain& up,
                                const CompensationChain& down, double h) {
  const CommandContext warm{{}, 0.0, 30.0, NAN};  // the thermal effect acts at 30 degC
  ParameterCovariance covariance;
  covariance.names = {name};
  covariance.covariance = Eigen::MatrixXd::Identity(1, 1);
  const auto sigma = ToolPoseCovariance(chain, q, warm, covariance);
  ASSERT_TRUE(sigma.has_value()) << name;
  Pose a, b;
  ASSERT_TRUE(ToolPose(up, q, warm, &a) && ToolPose(down, q, warm, &b));
  EXPECT_GT(sigma->trace(), 0.0) << name;
  Eigen::Matrix<double, 6, 1> numeric;
  numeric << (a.t - b.t) / (2 * h), RotationError(a.R, b.R) / (2 * h);
  const Eigen::Matrix<double, 6, 1> propagated = sigma->diagonal().cwiseSqrt();
  EXPECT_LT((propagated - numeric.cwiseAbs()).cwiseAbs().maxCoeff(),
            1e-6 * std::max(1.0, numeric.cwiseAbs().maxCoeff()))
      << name;
}

TEST(CompensateSigma, PropagatesThroughExactDerivatives) {
  const auto chain = MemoryChain("ur3_vsb2020.yaml", {"{type: thermal_drift}"}, {{1.2e-5}});
  const std::vector<double> q = {0.3, 3.2, -1.1, 0.4, 1.6, -0.7};
  const double h = 1e-6;
  auto moved = [&](auto change) {
    std::pair<CompensationChain, CompensationChain> out{chain, chain};
    change(&out.first, h);
    change(&out.second, -h);
    return out;
  };
  const int j3a = 2 * 5 + 1;  // serial_mdh: alpha a beta d offset per joint; joint 3's a
  ASSERT_EQ(chain.model->parameters()[j3a].name, "j3.a");
  auto model = moved([&](CompensationChain* c, double d) { c->params[j3a] += d; });
  ExpectPropagatedDerivative(chain, q, "ur3.model.j3.a", model.first, model.second, h);
  auto base = moved([](CompensationChain* c, double d) {
    const Eigen::Vector3d r(d, 0, 0);
    c->T_world_base.R = RotationFromRvec(r.data()) * c->T_world_base.R;
  });
  ExpectPropagatedDerivative(chain, q, "ur3.base.rx", base.first, base.second, h);
  auto tool = moved([](CompensationChain* c, double d) { c->T_flange_tool.t.z() += d; });
  ExpectPropagatedDerivative(chain, q, "tool.z", tool.first, tool.second, h);
  auto effect = moved([](CompensationChain* c, double d) { c->effect_values[0][0] += d; });
  ExpectPropagatedDerivative(chain, q, "ur3.effect0." + chain.effects[0]->parameters()[0].name,
                             effect.first, effect.second, h);
}

// One target row of `csv` (after its header) through Compensate on `chain`.
CompensatedCommand CompensateRow(const CompensationChain& chain, const std::string& header,
                                 const std::string& row, const CompensationOptions& options = {}) {
  const std::string path = testing::TempDirForThisTest("compensate") + "/targets.csv";
  testing::WriteText(path, header + "\n" + row + "\n");
  static std::vector<CompensationTarget> targets;  // the command points at its target
  targets = ReadCompensationTargets(path, chain.model->num_joints());
  return Compensate(chain, targets, ParameterCovariance{}, options).front();
}

// The nominal delta's tool position at motor angles `q`, as a TARGETS.csv row.
std::string DeltaRow(const CompensationChain& chain, const std::vector<double>& q) {
  Pose T;
  EXPECT_TRUE(ToolPose(chain, q, {}, &T));
  char text[128];
  std::snprintf(text, sizeof text, "%.17g,%.17g,%.17g", T.t.x(), T.t.y(), T.t.z());
  return text;
}

TEST(CompensateRefuses, TargetsOutOfReachOrPastJointLimitsInWords) {
  const auto delta = MemoryChain("delta.yaml", {}, {});
  const std::string xyz = "x_mm,y_mm,z_mm";
  // Motor 1 at 1.5 rad: the config's limit is 1.4.
  auto c = CompensateRow(delta, xyz, DeltaRow(delta, {1.5, 0.4, 0.4}));
  EXPECT_TRUE(c.refused);
  EXPECT_THAT(c.reason, HasSubstr("past joint limits: joint 1 would need 1.5 rad, above its "
                                  "limit 1.4 rad"));
  // Within the limits, but inside a margin asked for.
  CompensationOptions margin;
  margin.joint_limit_margin_rad = 0.1;
  c = CompensateRow(delta, xyz, DeltaRow(delta, {1.35, 0.4, 0.4}), margin);
  EXPECT_TRUE(c.refused);
  EXPECT_THAT(c.reason, HasSubstr("less the margin 0.1 rad"));
  EXPECT_FALSE(CompensateRow(delta, xyz, DeltaRow(delta, {1.35, 0.4, 0.4})).refused);
  // A metre below the arm: its rods cannot get there.
  c = CompensateRow(delta, xyz, "0,0,-1000");
  EXPECT_TRUE(c.refused);
  EXPECT_THAT(c.reason, HasSubstr("out of reach: "));

  const auto ur3 = MemoryChain("ur3_vsb2020.yaml", {}, {});
  const std::string pose = "x_mm,y_mm,z_mm,rx_rad,ry_rad,rz_rad";
  const std::string seed = ",q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";
  // Two metres from the base: the solve gets as close as the arm stretches, and says how close.
  c = CompensateRow(ur3, pose + seed, "2431,555,-460,0,0,0,0.3,3.2,-1.1,0.4,1.6,-0.7");
  EXPECT_TRUE(c.refused);
  EXPECT_THAT(c.reason, HasSubstr("out of reach: the calibrated robot comes no closer than"));
  // A serial arm's first target without a seed: which of its configurations is the user's call.
  c = CompensateRow(ur3, pose, "600,400,-300,0,3.14,0");
  EXPECT_TRUE(c.refused);
  EXPECT_THAT(c.reason, HasSubstr("no seed"));
}

TEST(CompensateRefuses, JointTargetsAreReachedAsTheNominalArmWouldReachThem) {
  // A joint target on an arm that is its nominal self needs no change, and says so.
  const auto ur3 = MemoryChain("ur3_vsb2020.yaml", {}, {});
  const auto c =
      CompensateRow(ur3, "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad", "0.3,3.2,-1.1,0.4,1.6,-0.7");
  ASSERT_FALSE(c.refused) << c.reason;
  const std::vector<double> expected = {0.3, 3.2, -1.1, 0.4, 1.6, -0.7};
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(c.q_rad[j], expected[j], 1e-12);
  EXPECT_NEAR(c.uncompensated_mm, 0.0, 1e-9);
}

// The command line: refused targets listed on standard error with file:line, exit code 3 unless
// --allow-refused, the other commands written either way; a user's file is never overwritten.
TEST(CompensateCli, RefusedTargetsExitThreeAndAreListed) {
  const FittedCell& cell = DeltaCell();
  const std::string dir = testing::TempDirForThisTest("compensate");
  testing::WriteText(dir + "/targets.csv",
                     "id,x_mm,y_mm,z_mm\n"
                     "good," +
                         DeltaRow(cell.chain, {0.4, 0.5, 0.6}) +
                         "\n"
                         "far,0,0,-1000\n");
  const std::string args =
      "compensate " + cell.result_folder + " " + dir + "/targets.csv -o " + dir + "/commands.csv";
  auto r = testing::RunCellmetry(args);
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr(dir + "/targets.csv:3: target 'far' refused: out of reach"));
  const std::string written = testing::ReadText(dir + "/commands.csv");
  EXPECT_THAT(written, HasSubstr("\ngood,2,ok,"));
  EXPECT_THAT(written, HasSubstr("\nfar,3,refused,"));
  EXPECT_THAT(written, HasSubstr("# effect applied: delta.backlash"));
  r = testing::RunCellmetry(args + " --allow-refused");  // replaces its own earlier file
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/commands.csv.previous"));
  testing::WriteText(dir + "/mine.csv", "a user's file\n");
  r = testing::RunCellmetry("compensate " + cell.result_folder + " " + dir + "/targets.csv -o " +
                            dir + "/mine.csv");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(testing::ReadText(dir + "/mine.csv"), "a user's file\n");
}

// A command beyond the joint ranges the calibration's poses span is not refused (the arm can
// reach it) but marked: its joints in the column beyond_calibration, the ranges in the opening
// comment, and a note on standard error. Here the result's recorded range of motor 1 is cut to
// start above the first target's 0.4 rad.
TEST(CompensateCli, CommandsBeyondTheCalibrationsJointRangesAreMarked) {
  const FittedCell& cell = DeltaCell();
  const std::string dir = testing::TempDirForThisTest("compensate_beyond");
  nlohmann::json result =
      nlohmann::json::parse(testing::ReadText(cell.result_folder + "/result.json"));
  auto& ranges = result["robots"]["delta"]["joint_ranges_rad"];
  ASSERT_EQ(ranges.size(), 3u);
  for (const auto& range : ranges) {  // the simulation's poses: -0.6 to 1.4 rad
    EXPECT_LT(range[0].get<double>(), -0.4);
    EXPECT_GT(range[1].get<double>(), 1.2);
  }
  ranges[0][0] = 0.45;
  fs::create_directories(dir + "/fit");
  testing::WriteText(dir + "/fit/result.json", result.dump());
  testing::WriteText(dir + "/targets.csv",
                     "id,x_mm,y_mm,z_mm\n"
                     "low," +
                         DeltaRow(cell.chain, {0.4, 0.5, 0.6}) +
                         "\n"
                         "inside," +
                         DeltaRow(cell.chain, {0.6, 0.5, 0.6}) + "\n");
  const auto r = testing::RunCellmetry("compensate " + dir + "/fit " + dir + "/targets.csv -o " +
                                       dir + "/commands.csv");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("note: 1 of 2 commands put a joint beyond the ranges the "
                                  "calibration's poses span"));
  const std::string written = testing::ReadText(dir + "/commands.csv");
  EXPECT_THAT(written, HasSubstr("# beyond_calibration: the joints a command puts outside the "
                                 "ranges the calibration's poses span (deg: 25.8.."));
  EXPECT_THAT(written, HasSubstr(",approach_j3,beyond_calibration,reason\n"));
  EXPECT_THAT(written, ::testing::ContainsRegex("\nlow,2,ok,[^\n]*,1,\n"));
  EXPECT_THAT(written, ::testing::ContainsRegex("\ninside,3,ok,[^\n]*,,\n"));
}

TEST(CompensateTargets, RotationsAreRefusedForAnArmThatCannotTurnItsTool) {
  const std::string path = testing::TempDirForThisTest("compensate") + "/targets.csv";
  testing::WriteText(path, "x_mm,y_mm,z_mm,rx_rad,ry_rad,rz_rad\n0,0,-600,0,0,0.1\n");
  const InputError e = testing::CatchInputError([&] { ReadCompensationTargets(path, 3); });
  EXPECT_EQ(FormatLocation(e.where()), path + ":1: ");
  EXPECT_THAT(e.message(), HasSubstr("the robot has 3 joints: it cannot turn its tool at will"));
  // Six joints take them; a row may leave its rotation out, or be a joint target.
  testing::WriteText(path,
                     "x_mm,y_mm,z_mm,rx_rad,ry_rad,rz_rad,q1_rad,q2_rad,q3_rad,q4_rad,"
                     "q5_rad,q6_rad\n1,2,3,0,0,0.1,,,,,,\n1,2,3,,,,,,,,,\n"
                     ",,,,,,1,2,3,4,5,6\n");
  const auto targets = ReadCompensationTargets(path, 6);
  ASSERT_EQ(targets.size(), 3u);
  EXPECT_EQ(targets[0].kind, CompensationTarget::Kind::kPose);
  EXPECT_EQ(targets[1].kind, CompensationTarget::Kind::kPosition);
  EXPECT_EQ(targets[2].kind, CompensationTarget::Kind::kJoints);
  EXPECT_EQ(targets[2].q_rad, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(targets[2].line, 4);
}

}  // namespace
}  // namespace cellmetry

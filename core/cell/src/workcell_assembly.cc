// Turning a recording into a workcell Problem: pairing observations with robots and cameras, the
// parameter blocks, and one residual per measured quantity (workcell_assembly.h).
#include "cellmetry/cell/workcell_assembly.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "cellmetry/basics/error.h"
#include "chain_cost.h"
#include "effect_chain_cost.h"
#include "forward_memo.h"
#include "jet_costs.h"
#include "joint_space_residual.h"
#include "workcell_residuals.h"

namespace cellmetry {
namespace {

Pose ObservedPose(const Observation& obs) {
  return Pose{obs.rvec ? RotationFromRvec(obs.rvec->data()) : Eigen::Matrix3d::Identity(),
              obs.position_mm};
}

// Frame block starting at `start`: translation as values, rotation as R_ref.
int AddFrameBlock(AssembledWorkcell* out, const std::string& name, FrameBlockSpec spec,
                  const Pose& start) {
  spec.start = start;
  const int id = out->problem.AddBlock(name, FrameParameters(spec));
  out->R_ref[id] = start.R;
  return id;
}

// A base standing level: priors on its rotation about the world's x and y (frame_block.h: R =
// exp(w) R_ref) at the w that turns R_ref's z axis onto the world's (or onto its opposite, for a
// base hung from a ceiling) by the shortest way. For a
// small tilt w's x and y are the tilt of the base's z axis about those axes, to first order.
void AddLevelPrior(AssembledWorkcell* out, int base_block, double sigma_rad) {
  const Eigen::Vector3d z_ref = out->R_ref.at(base_block).col(2);
  // Hung from a ceiling, a level base's z axis points down.
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() * (z_ref.z() < 0.0 ? -1.0 : 1.0);
  const Eigen::Vector3d axis = z_ref.cross(up);
  const double angle = std::atan2(axis.norm(), z_ref.dot(up));
  const Eigen::Vector3d w_level =
      axis.norm() > 1e-15 ? Eigen::Vector3d(axis.normalized() * angle) : Eigen::Vector3d::Zero();
  for (int i = 0; i < 2; ++i) out->problem.SetPrior(base_block, 3 + i, w_level[i], sigma_rad);
}

}  // namespace

namespace {

// The parameter blocks: per robot its base, model and tools; static cameras; effects.
void AddBlocks(const WorkcellProblem& spec, const WorkcellEstimate& start, AssembledWorkcell* out) {
  for (const auto& robot : spec.robots) {
    out->base_block.push_back(
        AddFrameBlock(out, robot.name + ".base", robot.base, start.T_world_base.at(robot.name)));
    if (robot.level_sigma_rad) {
      AddLevelPrior(out, out->base_block.back(), *robot.level_sigma_rad);
    }
    std::vector<Parameter> model_params = robot.model_parameters;
    const auto& values = start.model.at(robot.name);
    for (size_t i = 0; i < model_params.size(); ++i) model_params[i].nominal = values[i];
    out->model_block.push_back(out->problem.AddBlock(robot.name + ".model", model_params));
    std::vector<int> tools;
    for (const auto& tool : robot.tools) {
      tools.push_back(
          AddFrameBlock(out, tool.target, tool.flange_tool, start.T_flange_target.at(tool.target)));
    }
    out->tool_block.push_back(tools);
  }
  if (spec.camera_model == CameraModel::kStaticCameras) {
    for (const auto& [camera, T_world_cam] : start.T_world_cam) {
      FrameBlockSpec camera_spec;
      camera_spec.free.fill(true);
      const auto given = spec.cameras.find(camera);
      if (given != spec.cameras.end()) camera_spec.free = given->second.free;
      camera_spec.description = "camera pose in the world";
      out->camera_block[camera] = AddFrameBlock(out, camera, camera_spec, T_world_cam);
    }
  }
  for (const WorkcellEffect& e : spec.effects) {
    std::vector<Parameter> params = e.effect->parameters();
    const auto values = start.effects.find(e.name);
    for (size_t i = 0; i < params.size(); ++i) {
      params[i].nominal = values != start.effects.end() ? values->second.at(i) : 0.0;
      if (!e.held_values.empty()) {
        params[i].nominal = e.held_values.at(i);
        params[i].fixed = true;
      }
    }
    out->effect_block.push_back(out->problem.AddBlock(e.name, params));
  }
}

// The effects in a robot's chain (its own and every measurement effect) and their blocks;
// `robot` empty: the measurement effects alone (the world target's chain).
void ChainEffects(const WorkcellProblem& spec, const AssembledWorkcell& out,
                  const std::string& robot, std::vector<const Effect*>* effects,
                  std::vector<int>* blocks) {
  for (size_t k = 0; k < spec.effects.size(); ++k) {
    const WorkcellEffect& e = spec.effects[k];
    if (e.effect->stage() == EffectStage::kMeasurement || (!robot.empty() && e.robot == robot)) {
      effects->push_back(e.effect.get());
      blocks->push_back(out.effect_block[k]);
    }
  }
}

std::vector<int> BlockSizes(const Problem& problem, const std::vector<int>& blocks) {
  std::vector<int> sizes;
  for (int b : blocks) sizes.push_back(static_cast<int>(problem.block_parameters(b).size()));
  return sizes;
}

MeasurementLabel LabelFor(const Recording& recording, int observation) {
  const Observation& obs = recording.observations[observation];
  MeasurementLabel label;
  label.observation = observation;
  label.sample = obs.sample;
  label.pose = recording.samples[recording.SampleIndex(obs.sample)].pose;
  label.camera = obs.camera;
  label.target = obs.target;
  return label;
}

// A residual block measuring `observation` of `recording`, weighed by `sigma`, and its label:
// out->labels stays parallel to the problem's measurement blocks.
void AddMeasurement(const Recording& recording, int observation, ResidualInfo::Kind kind,
                    const Eigen::Vector3d& sigma, std::unique_ptr<ceres::CostFunction> cost,
                    const std::vector<int>& blocks, AssembledWorkcell* out) {
  ResidualInfo info;
  info.kind = kind;
  info.sigma = sigma;
  out->problem.AddResidual(std::move(cost), blocks, info);
  out->labels.push_back(LabelFor(recording, observation));
}

ResidualInfo::Kind KindOf(bool position) {
  return position ? ResidualInfo::Kind::kPosition : ResidualInfo::Kind::kRotation;
}

// Each capture's forward kinematics, shared by every block that reads it (forward_memo.h): by
// robot model and joint values. By the values, not the capture: the repeated captures of one
// pose read the same joints (exp_a: 10 per pose), and one chain serves all of them.
// Looked up by a capture's joints where they are (a copy of them per lookup was one allocation
// per block); the first capture's values stand for the memo's key, so they outlive the map.
struct JointsKey {
  const RobotModel* model;
  const double* q;  // model->num_joints() values
};
struct JointsOrder {
  bool operator()(const JointsKey& a, const JointsKey& b) const {
    if (a.model != b.model) return a.model < b.model;
    return std::lexicographical_compare(a.q, a.q + a.model->num_joints(), b.q,
                                        b.q + b.model->num_joints());
  }
};
using ForwardMemos = std::map<JointsKey, std::shared_ptr<ForwardMemo>, JointsOrder>;

// `q`: model->num_joints() values that outlive the memo (a capture's, for as long as the data).
std::shared_ptr<ForwardMemo> MemoFor(const RobotModel* model, const double* q,
                                     ForwardMemos* memos) {
  auto& memo = (*memos)[JointsKey{model, q}];
  if (!memo) memo = std::make_shared<ForwardMemo>(model, q);
  return memo;
}

// The first cost of each prediction, for the later ones to name (chain_cost.h,
// effect_chain_cost.h): by the forward-kinematics memo (the joints; null for the world target),
// the frame refs (which stand for the blocks), the compared quantity and, where measurement
// effects act, the measured target. Per memo a short list: its pose's cameras and quantities (a
// map over every block was a third of the factory cell's assembly).
template <typename Cost>
struct FirstCost {
  const FrameRefs* refs;
  Compared compared;
  std::string target;
  const Cost* cost;
};
template <typename Cost>
using FirstCosts = std::unordered_map<const ForwardMemo*, std::vector<FirstCost<Cost>>>;

// The first cost of this prediction (null, to be set by the caller, when there is none yet).
template <typename Cost>
const Cost*& FirstOf(const ForwardMemo* memo, const FrameRefs* refs, Compared compared,
                     const std::string& target, FirstCosts<Cost>* firsts) {
  std::vector<FirstCost<Cost>>& costs = (*firsts)[memo];
  for (FirstCost<Cost>& first : costs) {
    if (first.refs == refs && first.compared == compared && first.target == target) {
      return first.cost;
    }
  }
  costs.push_back({refs, compared, target, nullptr});
  return costs.back().cost;
}

// Whether blocks with these effects predict the same from the same joints, frames, camera and
// target: none of them reads what differs from capture to capture.
bool SharedByCaptures(const std::vector<const Effect*>& effects) {
  for (const Effect* effect : effects) {
    const EffectNeeds needs = effect->needs();
    if (needs.time || needs.temperature || needs.payload || needs.approach) return false;
  }
  return true;
}

// The effects in a robot's chain (`robot` empty: the world target's), once per assembly.
struct RobotEffects {
  std::shared_ptr<const ChainEffectList> list;
  std::vector<int> blocks;  // their parameter blocks
  bool shared_by_captures = true;
};

RobotEffects EffectsOf(const WorkcellProblem& spec, const AssembledWorkcell& out,
                       const std::string& robot) {
  std::vector<const Effect*> effects;
  RobotEffects chain;
  ChainEffects(spec, out, robot, &effects, &chain.blocks);
  chain.shared_by_captures = SharedByCaptures(effects);
  chain.list = std::make_shared<const ChainEffectList>(std::move(effects),
                                                       BlockSizes(out.problem, chain.blocks));
  return chain;
}

// What every observation of one target by one camera shares in an assembly: the camera's
// block and the pair's noise, looked up by name once per pair instead of once per observation
// (the lookups by name were a fifth of assembling exp_a's 22,500 blocks).
struct CameraTarget {
  std::string camera, target;
  int camera_block = -1;  // -1: the camera has no block (per-frame camera model)
  const TargetNoise* noise = nullptr;
};

class CameraTargets {
 public:
  CameraTargets(const AssembledWorkcell& out, const NoiseModel& noise) : out_(out), noise_(noise) {}

  // Observations come capture by capture, a few cameras and targets in turn: a short scan.
  const CameraTarget& Of(const Observation& obs) {
    for (const CameraTarget& known : known_) {
      if (known.camera == obs.camera && known.target == obs.target) return known;
    }
    CameraTarget& added = known_.emplace_back();
    added.camera = obs.camera;
    added.target = obs.target;
    const auto block = out_.camera_block.find(obs.camera);
    if (block != out_.camera_block.end()) added.camera_block = block->second;
    added.noise = &noise_.at(obs.camera, obs.target);
    return added;
  }

 private:
  const AssembledWorkcell& out_;
  const NoiseModel& noise_;
  std::deque<CameraTarget> known_;  // at stable addresses
};

// Everything one carried-target measurement's residuals need.
struct ToolContext {
  const WorkcellProblem& spec;
  const Recording& recording;
  const WorkcellData& data;
  const WorkcellEstimate& start;
  const ToolMeasurement& m;
  FrameRefs refs;
  std::vector<int> blocks;  // base, tool, [camera]
  bool static_camera = false;
  bool model_free = false;
  ForwardMemos* memos = nullptr;
  std::shared_ptr<const FrameRefs> shared_refs;  // `refs`, shared by the blocks of its frames
  FirstCosts<ChainCost>* first_costs = nullptr;
  FirstCosts<EffectChainCost>* first_effect_costs = nullptr;
  const std::vector<RobotEffects>* effects = nullptr;  // per robot
};

// One FrameRefs per combination of frame blocks (ChainCost's shared constructor): by block ids.
using SharedRefs = std::map<std::vector<int>, std::shared_ptr<const FrameRefs>>;

std::shared_ptr<const FrameRefs> Shared(const std::vector<int>& blocks, const FrameRefs& refs,
                                        SharedRefs* shared) {
  auto& entry = (*shared)[blocks];
  if (!entry) entry = std::make_shared<const FrameRefs>(refs);
  return entry;
}

// The blocks of a Jet chain residual, as JetChainLayout orders them (held frames left out).
std::vector<int> JetBlocks(const ToolContext& c, const AssembledWorkcell& out) {
  std::vector<int> blocks;
  if (!c.refs.held_world_base) blocks.push_back(c.blocks[0]);
  if (!c.refs.held_flange_target) blocks.push_back(c.blocks[1]);
  if (c.static_camera) blocks.push_back(c.blocks[2]);
  blocks.push_back(out.model_block[c.m.robot]);
  return blocks;
}

// d q / d p_cam at the start: how a measured point's error moves the joints (inverse kinematics
// differentiated on Jets through the start's camera, base and tool).
// Where the measured point puts the flange, at the start (base frame, mm).
Eigen::Vector3d FlangeOfPoint(const ToolContext& c, Pose* T_base_cam) {
  const Observation& obs = c.recording.observations[c.m.observation];
  const WorkcellRobot& robot = c.spec.robots[c.m.robot];
  *T_base_cam = c.start.T_world_base.at(robot.name).inverse() * c.start.T_world_cam.at(obs.camera);
  return *T_base_cam * obs.position_mm - c.start.T_flange_target.at(robot.tools[c.m.tool].target).t;
}

bool JointsFromPoint(const ToolContext& c, Eigen::Vector3d* q_out, Eigen::Matrix3d* d_q_d_p) {
  const WorkcellRobot& robot = c.spec.robots[c.m.robot];
  Pose T_base_cam;
  const Eigen::Vector3d flange = FlangeOfPoint(c, &T_base_cam);
  const auto& values = c.start.model.at(robot.name);
  const std::vector<Jet> params(values.begin(), values.end());
  Jet position[3], q[3];
  for (int i = 0; i < 3; ++i) {
    position[i] = Jet(flange[i]);
    for (int k = 0; k < 3; ++k) position[i].v[k] = T_base_cam.R(i, k);
  }
  if (!robot.model->Inverse(position, params.data(), q)) return false;
  for (int i = 0; i < 3; ++i) {
    (*q_out)[i] = q[i].a;
    for (int k = 0; k < 3; ++k) (*d_q_d_p)(i, k) = q[i].v[k];
  }
  return true;
}

// The joint-space residual of one measured position (joint_space_residual.h).
std::unique_ptr<ceres::CostFunction> JointSpaceCost(const ToolContext& c, AssembledWorkcell* out,
                                                    const Eigen::Vector3d& sigma_mm,
                                                    std::vector<int>* blocks) {
  const Observation& obs = c.recording.observations[c.m.observation];
  const WorkcellRobot& robot = c.spec.robots[c.m.robot];
  Eigen::Vector3d q;
  Eigen::Matrix3d J;
  if (!JointsFromPoint(c, &q, &J)) {
    Pose T_base_cam;
    const Eigen::Vector3d flange = FlangeOfPoint(c, &T_base_cam);
    throw InputError(
        {c.recording.folder + "/observations.csv", obs.line, 0},
        "the measured point is out of the arm's reach: " +
            robot.model->InverseFailure(flange.data(), c.start.model.at(robot.name).data()),
        "Check the camera pose and tool offset, or remove this observation");
  }
  *blocks = JetBlocks(c, *out);
  const Sample& sample = c.recording.samples[c.m.sample_index];
  return JointSpaceCostFunction(c.refs, robot.model.get(), sample.q, obs.position_mm,
                                JointWhitening(J, sigma_mm), out->problem, *blocks);
}

// What an EffectChainCost of `c` reads of its sample: the sample's facts where the cell has
// effects (PrepareWorkcellData gathers them only then), else its joints, all a chain without
// effects reads.
EffectContext ChainContext(const ToolContext& c) {
  const Observation& obs = c.recording.observations[c.m.observation];
  EffectContext context;
  if (!c.data.facts.empty()) {
    context = ContextOf(c.data.facts.at(c.m.sample_index), c.spec.gravity_base, obs.camera);
  } else {
    const Sample& sample = c.recording.samples[c.m.sample_index];
    context.num_joints = static_cast<int>(sample.q.size());
    context.q = sample.q.data();
    context.camera = obs.camera;
  }
  context.target = obs.target;
  return context;
}

// The cost of comparing one carried target's `compared` quantity, and the blocks it reads.
std::unique_ptr<ceres::CostFunction> ToolCost(const ToolContext& c, AssembledWorkcell* out,
                                              const TargetComparison& comparison,
                                              std::vector<int>* blocks) {
  const Observation& obs = c.recording.observations[c.m.observation];
  const WorkcellRobot& robot = c.spec.robots[c.m.robot];
  const Sample& sample = c.recording.samples[c.m.sample_index];
  const RobotEffects& in_chain = c.effects->at(static_cast<size_t>(c.m.robot));
  // A free model takes the effect chain's closed-form model twists even without effects: Jets
  // over the whole chain would run a UR3's forward kinematics six times per residual for its 24
  // parameters and the frames, most of a diagnosis with every MDH entry free.
  if (!in_chain.list->effects.empty() || c.model_free) {
    EffectContext context = ChainContext(c);
    blocks->push_back(out->model_block[c.m.robot]);
    blocks->insert(blocks->end(), in_chain.blocks.begin(), in_chain.blocks.end());
    auto forward = MemoFor(robot.model.get(), context.q, c.memos);
    // A moving camera's measured pose is a factor of the prediction: those are not shared.
    const EffectChainCost* none = nullptr;
    const EffectChainCost*& first =
        c.static_camera && in_chain.shared_by_captures
            ? FirstOf(forward.get(), c.shared_refs.get(), comparison.compared(), obs.target,
                      c.first_effect_costs)
            : none;
    auto cost = std::make_unique<EffectChainCost>(comparison, c.shared_refs, robot.model.get(),
                                                  context, c.static_camera, c.m.T_cam_world,
                                                  in_chain.list, std::move(forward), first);
    if (first == nullptr) first = cost.get();
    return cost;
  }
  Pose T_base_flange;
  const std::shared_ptr<ForwardMemo> memo = MemoFor(robot.model.get(), sample.q.data(), c.memos);
  if (!memo->Forward(c.start.model.at(robot.name).data(), &T_base_flange, nullptr)) {
    throw InputError(
        {c.recording.folder + "/samples.csv", sample.line, 0},
        "robot '" + robot.name + "' has no pose for sample " + std::to_string(sample.id),
        "Check the joint values against the robot model");
  }
  const ChainBlocks chain{/*base=*/true, /*tool=*/true, /*camera=*/c.static_camera};
  // A moving camera's measured pose is a factor of the prediction: those are not shared.
  if (!c.static_camera) {
    return std::make_unique<ChainCost>(comparison, c.shared_refs, chain, T_base_flange,
                                       c.m.T_cam_world);
  }
  const ChainCost*& first =
      FirstOf(memo.get(), c.shared_refs.get(), comparison.compared(), "", c.first_costs);
  auto cost = std::make_unique<ChainCost>(comparison, c.shared_refs, chain, T_base_flange,
                                          c.m.T_cam_world, first);
  if (first == nullptr) first = cost.get();
  return cost;
}

bool BlockHeld(const AssembledWorkcell& out, int block) {
  for (const auto& p : out.problem.block_parameters(block)) {
    if (!p.fixed) return false;
  }
  return true;
}

bool ModelFree(const AssembledWorkcell& out, int robot) {
  for (const auto& p : out.problem.block_parameters(out.model_block[robot])) {
    if (!p.fixed) return true;
  }
  return false;
}

// The residuals of one world-target observation by a camera riding on a flange (eye in hand):
// its position and its rotation, on Jets (eye_in_hand_residual.h).
void AddEyeInHandResiduals(const Recording& recording, const ToolMeasurement& m,
                           const WorkcellRobot& robot, const TargetNoise& sigma,
                           AssembledWorkcell* out) {
  const Observation& obs = recording.observations[m.observation];
  const std::vector<int> blocks = {out->base_block[m.robot], out->tool_block[m.robot][m.tool],
                                   out->model_block[m.robot]};
  const Pose observed = ObservedPose(obs);
  for (Compared what : {Compared::kPosition, Compared::kRotation}) {
    const bool position = what == Compared::kPosition;
    const Eigen::Vector3d s = position ? RowPositionSigma(sigma, obs) : sigma.rotation_rad;
    auto cost = EyeInHandCostFunction(TargetComparison(what, observed, s), out->R_ref.at(blocks[0]),
                                      out->R_ref.at(blocks[1]), robot.model.get(),
                                      recording.samples[m.sample_index].q, out->problem, blocks);
    AddMeasurement(recording, m.observation, KindOf(position), s, std::move(cost), blocks, out);
  }
}

// What the carried-target residuals of one assembly share: forward kinematics by joints, frame
// references by blocks, the first cost of each shape, and each robot's effects.
struct ToolCaches {
  ForwardMemos memos;
  SharedRefs shared_refs;
  FirstCosts<ChainCost> first_costs;
  FirstCosts<EffectChainCost> first_effect_costs;
  std::vector<RobotEffects> effects;  // per robot
};

// A carried-target measurement's context: its blocks (base, tool, and the static camera's),
// their reference rotations (a held frame's pose with them), and the shared caches.
ToolContext CarriedTargetContext(const WorkcellProblem& spec, const Recording& recording,
                                 const WorkcellData& data, const WorkcellEstimate& start,
                                 const ToolMeasurement& m, const CameraTarget& seen,
                                 ToolCaches* caches, const AssembledWorkcell& out) {
  ToolContext c{spec, recording, data, start, m, {}, {}, false, false, nullptr, nullptr, nullptr};
  c.static_camera = spec.camera_model == CameraModel::kStaticCameras;
  c.model_free = ModelFree(out, m.robot);
  c.memos = &caches->memos;
  c.first_costs = &caches->first_costs;
  c.first_effect_costs = &caches->first_effect_costs;
  c.effects = &caches->effects;
  c.blocks = {out.base_block[m.robot], out.tool_block[m.robot][m.tool]};
  c.refs.world_base = out.R_ref.at(c.blocks[0]);
  if (BlockHeld(out, c.blocks[0])) {
    c.refs.held_world_base = FrameFromBlock(out.problem.values(c.blocks[0]), c.refs.world_base);
  }
  c.refs.flange_target = out.R_ref.at(c.blocks[1]);
  if (BlockHeld(out, c.blocks[1])) {
    c.refs.held_flange_target =
        FrameFromBlock(out.problem.values(c.blocks[1]), c.refs.flange_target);
  }
  if (c.static_camera) {
    c.blocks.push_back(seen.camera_block);
    c.refs.world_cam = out.R_ref.at(c.blocks[2]);
  }
  c.shared_refs = Shared(c.blocks, c.refs, &caches->shared_refs);
  return c;
}

// A carried target's residuals: its position (and rotation where the job compares it) in the
// job's residual form.
void AddCarriedTargetResiduals(const ToolContext& c, const Observation& obs,
                               const TargetNoise& sigma, AssembledWorkcell* out) {
  if (c.spec.residual == ResidualForm::kJointSpace) {
    std::vector<int> blocks = c.blocks;
    auto cost = JointSpaceCost(c, out, RowPositionSigma(sigma, obs), &blocks);
    AddMeasurement(c.recording, c.m.observation, ResidualInfo::Kind::kPosition,
                   Eigen::Vector3d::Ones(),  // its rows: whitened joint errors
                   std::move(cost), blocks, out);
    return;
  }
  std::vector<Compared> compared = {Compared::kPosition};
  if (c.spec.use_tool_rotation) compared.push_back(Compared::kRotation);
  const Pose observed = ObservedPose(obs);
  for (Compared what : compared) {
    const bool position = what == Compared::kPosition;
    const Eigen::Vector3d s = position ? RowPositionSigma(sigma, obs) : sigma.rotation_rad;
    std::vector<int> blocks = c.blocks;
    auto cost = ToolCost(c, out, TargetComparison(what, observed, s), &blocks);
    AddMeasurement(c.recording, c.m.observation, KindOf(position), s, std::move(cost), blocks, out);
  }
}

// Residuals of every carried-target measurement of `poses` (empty: all).
void AddToolResiduals(const WorkcellProblem& spec, const Recording& recording,
                      const WorkcellData& data, const NoiseModel& noise,
                      const WorkcellEstimate& start, const std::set<int>& poses,
                      AssembledWorkcell* out) {
  ToolCaches caches;
  for (const WorkcellRobot& robot : spec.robots) {
    caches.effects.push_back(EffectsOf(spec, *out, robot.name));
  }
  CameraTargets camera_targets(*out, noise);
  for (const ToolMeasurement& m : data.tools) {
    const Sample& sample = recording.samples[m.sample_index];
    if (!poses.empty() && !poses.count(sample.pose)) continue;
    const Observation& obs = recording.observations[m.observation];
    const CameraTarget& seen = camera_targets.Of(obs);
    if (spec.robots[m.robot].tools[m.tool].is_camera()) {
      AddEyeInHandResiduals(recording, m, spec.robots[m.robot], *seen.noise, out);
      continue;
    }
    const ToolContext c =
        CarriedTargetContext(spec, recording, data, start, m, seen, &caches, *out);
    AddCarriedTargetResiduals(c, obs, *seen.noise, out);
  }
}

// Residuals of the world target's observations: measurements of the static cameras' poses.
void AddWorldResiduals(const WorkcellProblem& spec, const Recording& recording,
                       const WorkcellData& data, const NoiseModel& noise,
                       const std::set<int>& poses, AssembledWorkcell* out) {
  const RobotEffects in_chain = EffectsOf(spec, *out, "");
  FirstCosts<ChainCost> first_costs;
  FirstCosts<EffectChainCost> first_effect_costs;
  CameraTargets camera_targets(*out, noise);
  std::unordered_map<int, std::shared_ptr<const FrameRefs>> refs_of_camera;  // by camera block
  for (int index : data.world_observations) {
    const Observation& obs = recording.observations[index];
    if (!poses.empty() && !poses.count(recording.samples[recording.SampleIndex(obs.sample)].pose)) {
      continue;
    }
    const CameraTarget& seen = camera_targets.Of(obs);
    const int camera = seen.camera_block;
    if (camera < 0) throw std::logic_error("a world-target observation of a camera without a pose");
    std::shared_ptr<const FrameRefs>& camera_refs = refs_of_camera[camera];
    if (!camera_refs) {
      FrameRefs refs;
      refs.world_cam = out->R_ref.at(camera);
      camera_refs = std::make_shared<const FrameRefs>(refs);
    }
    const TargetNoise& sigma = *seen.noise;
    const Pose observed = ObservedPose(obs);
    for (Compared what : {Compared::kPosition, Compared::kRotation}) {
      const bool position = what == Compared::kPosition;
      const Eigen::Vector3d s = position ? RowPositionSigma(sigma, obs) : sigma.rotation_rad;
      const TargetComparison comparison(what, observed, s);
      std::vector<int> blocks = {camera};
      std::unique_ptr<ceres::CostFunction> cost;
      if (!in_chain.list->effects.empty()) {
        EffectContext context;
        context.camera = obs.camera;
        context.target = obs.target;
        blocks.insert(blocks.end(), in_chain.blocks.begin(), in_chain.blocks.end());
        // Every observation of this world tag by this camera predicts the same measured pose.
        const EffectChainCost* none = nullptr;
        const EffectChainCost*& first =
            in_chain.shared_by_captures
                ? FirstOf(nullptr, camera_refs.get(), what, obs.target, &first_effect_costs)
                : none;
        auto effect_cost = std::make_unique<EffectChainCost>(
            comparison, camera_refs, /*model=*/nullptr, context, /*static_camera=*/true,
            Pose::Identity(), in_chain.list, /*forward=*/nullptr, first);
        if (first == nullptr) first = effect_cost.get();
        cost = std::move(effect_cost);
      } else {
        const ChainBlocks camera_only{/*base=*/false, /*tool=*/false, /*camera=*/true};
        // Every world-tag observation of this camera predicts the same: the world in it.
        const ChainCost*& first = FirstOf(nullptr, camera_refs.get(), what, "", &first_costs);
        auto chain_cost = std::make_unique<ChainCost>(comparison, camera_refs, camera_only,
                                                      Pose::Identity(), Pose::Identity(), first);
        if (first == nullptr) first = chain_cost.get();
        cost = std::move(chain_cost);
      }
      AddMeasurement(recording, index, KindOf(position), s, std::move(cost), blocks, out);
    }
  }
}

}  // namespace

std::unique_ptr<AssembledWorkcell> AssembleWorkcell(
    const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
    const NoiseModel& noise, const WorkcellEstimate& start, const std::set<int>& poses) {
  auto out = std::make_unique<AssembledWorkcell>();
  AddBlocks(spec, start, out.get());
  // At most this many measurement blocks (fewer for a subset of poses).
  const size_t per_tool = 2;  // position, and the rotation where fitted (eye in hand: always)
  const size_t world = spec.camera_model == CameraModel::kStaticCameras ? 2 : 0;
  const size_t measurements = per_tool * data.tools.size() + world * data.world_observations.size();
  out->problem.ReserveResiduals(static_cast<int>(measurements));
  out->labels.reserve(measurements);
  AddToolResiduals(spec, recording, data, noise, start, poses, out.get());
  if (spec.camera_model == CameraModel::kStaticCameras) {
    AddWorldResiduals(spec, recording, data, noise, poses, out.get());
  }
  out->problem.Build();
  return out;
}

WorkcellEstimate ReadEstimate(const WorkcellProblem& spec, const AssembledWorkcell& assembled) {
  WorkcellEstimate estimate;
  const Problem& problem = assembled.problem;
  auto frame = [&](int block) {
    return FrameFromBlock(problem.values(block), assembled.R_ref.at(block));
  };
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const auto& robot = spec.robots[r];
    estimate.T_world_base[robot.name] = frame(assembled.base_block[r]);
    const int model = assembled.model_block[r];
    estimate.model[robot.name].assign(problem.values(model),
                                      problem.values(model) + robot.model_parameters.size());
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      estimate.T_flange_target[robot.tools[t].target] = frame(assembled.tool_block[r][t]);
    }
  }
  for (const auto& [camera, block] : assembled.camera_block) {
    estimate.T_world_cam[camera] = frame(block);
  }
  for (size_t k = 0; k < spec.effects.size(); ++k) {
    const int block = assembled.effect_block[k];
    estimate.effects[spec.effects[k].name].assign(
        problem.values(block), problem.values(block) + problem.block_parameters(block).size());
  }
  return estimate;
}

}  // namespace cellmetry

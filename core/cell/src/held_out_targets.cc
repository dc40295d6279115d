// The held-out setup's measured targets as TARGETS.csv (held_out_targets.h).
#include "cellmetry/cell/held_out_targets.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/fixed_number.h"

namespace cellmetry {
namespace {

struct Row {
  const Sample* sample;
  Pose T_world_target;
  bool has_rotation;
};

std::vector<Row> ScoredRows(const HeldOutSetupScore& score, const Recording& held_out,
                            const std::string& target) {
  const std::set<int> registration(score.registration_poses.begin(),
                                   score.registration_poses.end());
  std::map<int, const Sample*> sample_of_id;
  for (const Sample& s : held_out.samples) sample_of_id[s.id] = &s;
  const auto& T_world_cam = score.registered->estimate.T_world_cam;
  std::vector<Row> rows;
  for (const Observation& obs : held_out.observations) {
    if (obs.target != target) continue;
    const auto sample = sample_of_id.find(obs.sample);
    const auto camera = T_world_cam.find(obs.camera);
    if (sample == sample_of_id.end() || camera == T_world_cam.end()) continue;
    if (registration.count(sample->second->pose)) continue;  // it registered the frames
    const Pose T_cam_target = obs.rvec ? PoseFromRvecT(*obs.rvec, obs.position_mm)
                                       : Pose{Eigen::Matrix3d::Identity(), obs.position_mm};
    rows.push_back({sample->second, camera->second * T_cam_target, obs.rvec.has_value()});
  }
  return rows;
}

std::string Number(double value) { return FixedNumber(value, 9); }

}  // namespace

std::string HeldOutTargetsCsv(const HeldOutSetupScore& score, const Recording& held_out,
                              const std::string& target) {
  const std::vector<Row> rows = ScoredRows(score, held_out, target);
  if (rows.empty()) {
    throw InputError({held_out.folder, 0, 0},
                     "no scored pose of the held-out setup saw target '" + target + "'",
                     "Name a target the held-out recording observes");
  }
  auto every = [&rows](auto has) { return std::all_of(rows.begin(), rows.end(), has); };
  const bool rotation = every([](const Row& r) { return r.has_rotation; });
  const bool payload = every([](const Row& r) { return r.sample->payload_kg.has_value(); });
  const bool temperature = every([](const Row& r) { return r.sample->temperature_c.has_value(); });
  const bool time = every([](const Row& r) { return r.sample->time_s.has_value(); });
  const size_t joints = rows.front().sample->q.size();

  std::ostringstream out;
  out << "# " << target << " where the instrument measured it at the scored poses of "
      << held_out.folder << ",\n# in the world of the registered result beside this file; "
      << "the seed q: the joints the robot reached it at\n";
  out << "id,x_mm,y_mm,z_mm" << (rotation ? ",rx_rad,ry_rad,rz_rad" : "");
  for (size_t j = 1; j <= joints; ++j) out << ",q" << j << "_rad";
  out << (payload ? ",payload_kg" : "") << (temperature ? ",temperature_c" : "")
      << (time ? ",t_s" : "") << "\n";
  for (const Row& r : rows) {
    const Eigen::Vector3d& p = r.T_world_target.t;
    out << "pose " << r.sample->pose << " sample " << r.sample->id << "," << Number(p.x()) << ","
        << Number(p.y()) << "," << Number(p.z());
    if (rotation) {
      const Eigen::Vector3d rvec = RvecFromRotation(r.T_world_target.R);
      out << "," << Number(rvec.x()) << "," << Number(rvec.y()) << "," << Number(rvec.z());
    }
    for (double q : r.sample->q) out << "," << Number(q);
    if (payload) out << "," << Number(*r.sample->payload_kg);
    if (temperature) out << "," << Number(*r.sample->temperature_c);
    if (time) out << "," << Number(*r.sample->time_s);
    out << "\n";
  }
  return out.str();
}

void WriteHeldOutSetupFolder(const HeldOutSetupScore& score, const Recording& held_out,
                             const std::string& folder) {
  if (!score.registered) return;
  const std::filesystem::path path(folder);
  std::filesystem::create_directory(path);
  AtomicWriteFile((path / "result.yaml").string(), WorkcellResultYaml(*score.registered));
  AtomicWriteFile((path / "result.json").string(),
                  WorkcellResultJson(*score.registered).dump(2) + "\n");
  for (const auto& [target, carrier] : held_out.targets) {
    if (carrier == kWorldCarrier) continue;
    AtomicWriteFile((path / ("targets_" + target + ".csv")).string(),
                    HeldOutTargetsCsv(score, held_out, target));
  }
}

}  // namespace cellmetry

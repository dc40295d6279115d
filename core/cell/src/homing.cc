// Visual homing (homing.h): the interval algorithm and weighted least squares, side by side.
#include "cellmetry/cell/homing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// One position's measured homing offset and its propagated standard deviation, per motor.
struct MeasuredOffset {
  int sample = 0;
  Eigen::Vector3d offset_rad;
  Eigen::Vector3d sd_rad;
  Eigen::Matrix3d weight;  // (J Sigma J^T)^-1
};

// Joint values that put the marker at `p_cam` (inverse kinematics through the camera pose and
// marker offset) and their derivative d q / d p_cam, on Jets; false where out of reach.
bool InverseInCamera(const HomingArm& arm, const std::vector<double>& values,
                     const Eigen::Vector3d& p_cam, Eigen::Vector3d* q_out,
                     Eigen::Matrix3d* d_q_d_p_cam) {
  const Eigen::Vector3d flange = arm.T_base_cam * p_cam - arm.marker_mm;
  const std::vector<Jet> params(values.begin(), values.end());
  Jet position[3], q[3];
  for (int i = 0; i < 3; ++i) {
    position[i] = Jet(flange[i]);
    for (int k = 0; k < 3; ++k) position[i].v[k] = arm.T_base_cam.R(i, k);  // d flange / d p_cam
  }
  if (!arm.model->Inverse(position, params.data(), q)) return false;
  for (int i = 0; i < 3; ++i) {
    (*q_out)[i] = q[i].a;
    for (int k = 0; k < 3; ++k) (*d_q_d_p_cam)(i, k) = q[i].v[k];
  }
  return true;
}

std::vector<MeasuredOffset> MeasureOffsets(const HomingArm& arm,
                                           const std::vector<PointSample>& samples,
                                           const Eigen::Vector3d& sigma_mm) {
  std::vector<double> values;
  for (const auto& p : arm.model_parameters) values.push_back(p.nominal);
  std::vector<MeasuredOffset> out;
  for (const PointSample& s : samples) {
    Eigen::Vector3d q;
    Eigen::Matrix3d J;
    if (!InverseInCamera(arm, values, s.p_cam_mm, &q, &J)) {
      const Eigen::Vector3d flange = arm.T_base_cam * s.p_cam_mm - arm.marker_mm;
      throw InputError(s.measured_at,
                       "the measured point is out of the arm's reach: " +
                           arm.model->InverseFailure(flange.data(), values.data()),
                       "Check the camera pose and marker offset, or remove this observation");
    }
    // theta = q_ik + homing_estimate; the offset is theta - command (motor i: entry 5 i + 4).
    MeasuredOffset m;
    m.sample = s.sample;
    for (int i = 0; i < 3; ++i) {
      const int homing =
          FindParameter(arm.model_parameters, "arm" + std::to_string(i + 1) + ".homing");
      const double estimate = homing >= 0 ? arm.model_parameters[homing].nominal : 0.0;
      m.offset_rad[i] = q[i] + estimate - s.q[i];
    }
    const Eigen::Matrix3d cov = J * sigma_mm.cwiseAbs2().asDiagonal() * J.transpose();
    m.sd_rad = cov.diagonal().cwiseSqrt();
    m.weight = cov.inverse();
    out.push_back(m);
  }
  return out;
}

// Steps 1-2 on `pool` (offsets minus `applied`): intersect the narrowest intervals first until
// every motor's interval is narrower than the target. Consumes the positions it uses from pool.
HomingRun Intersect(std::vector<MeasuredOffset>* pool, const Eigen::Vector3d& applied,
                    const HomingOptions& options, double target_rad) {
  std::sort(pool->begin(), pool->end(), [](const MeasuredOffset& a, const MeasuredOffset& b) {
    return a.sd_rad.maxCoeff() < b.sd_rad.maxCoeff();
  });
  HomingRun run;
  run.lower_rad.setConstant(-INFINITY);
  run.upper_rad.setConstant(INFINITY);
  size_t used = 0;
  for (; used < pool->size(); ++used) {
    const MeasuredOffset& m = (*pool)[used];
    const Eigen::Vector3d middle = m.offset_rad - applied;
    const Eigen::Vector3d lo = run.lower_rad.cwiseMax(middle - options.n_sigma * m.sd_rad);
    const Eigen::Vector3d hi = run.upper_rad.cwiseMin(middle + options.n_sigma * m.sd_rad);
    if ((lo.array() > hi.array()).any()) {
      run.rejected.push_back(m.sample);  // outside n_sigma of the others: an outlier
      continue;
    }
    run.lower_rad = lo;
    run.upper_rad = hi;
    run.samples.push_back(m.sample);
    const bool narrow = ((hi - lo).array() < target_rad).all();
    if (narrow && static_cast<int>(run.samples.size()) >= options.min_positions) {
      ++used;
      break;
    }
  }
  pool->erase(pool->begin(), pool->begin() + used);
  return run;
}

std::string Describe(const Eigen::Vector3d& rad, double increment) {
  char text[128];
  std::snprintf(text, sizeof(text), "(%.2f, %.2f, %.2f) increments",
                InIncrements(rad[0], increment), InIncrements(rad[1], increment),
                InIncrements(rad[2], increment));
  return text;
}

}  // namespace

double InIncrements(double rad, double increment_rad) {
  return increment_rad > 0 ? rad / increment_rad : rad;
}

HomingResult HomeVisually(const HomingArm& arm, const std::vector<PointSample>& samples,
                          const Eigen::Vector3d& sigma_mm, const HomingOptions& options) {
  HomingResult result;
  result.increment_rad = arm.model->limits().joint_increment_rad;
  std::vector<MeasuredOffset> pool = MeasureOffsets(arm, samples, sigma_mm);
  result.positions = static_cast<int>(pool.size());
  if (result.positions < options.min_positions) {
    const std::string file = samples.empty() ? "" : samples.front().command_at.file;
    throw InputError({file, 0, 0},
                     "homing needs at least " + std::to_string(options.min_positions) +
                         " measured positions, the recording has " +
                         std::to_string(result.positions) + " usable",
                     "Record the marker at more positions (spread over the workspace)");
  }
  // Least squares over every position.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (const auto& m : pool) {
    information += m.weight;
    weighted += m.weight * m.offset_rad;
  }
  const Eigen::Matrix3d covariance = information.inverse();
  result.lsq_offset_rad = covariance * weighted;
  result.lsq_sigma_rad = covariance.diagonal().cwiseSqrt();

  // The interval algorithm, then validation reruns on the positions it has not used.
  const double target =
      options.target_width_increments * (result.increment_rad > 0 ? result.increment_rad : 1.0);
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  result.runs.push_back(Intersect(&pool, offset, options, target));
  const HomingRun& first = result.runs.front();
  offset = 0.5 * (first.lower_rad + first.upper_rad);
  result.interval_width_rad = first.upper_rad - first.lower_rad;
  for (int rerun = 0; rerun < options.max_reruns && !result.validated; ++rerun) {
    if (pool.empty()) {
      result.validation = "not validated: every position went into the estimate; record more";
      break;
    }
    result.runs.push_back(Intersect(&pool, offset, options, target));
    const HomingRun& check = result.runs.back();
    const Eigen::Vector3d residual = 0.5 * (check.lower_rad + check.upper_rad);
    const bool holds_zero =
        (check.lower_rad.array() <= 0).all() && (check.upper_rad.array() >= 0).all();
    const bool small =
        (residual.cwiseAbs().array() < (result.increment_rad > 0 ? result.increment_rad : target))
            .all();
    result.validated = holds_zero && small;
    result.validation = (result.validated ? "validated" : "corrected") + std::string(" on ") +
                        std::to_string(check.samples.size()) + " fresh positions: residual " +
                        Describe(residual, result.increment_rad);
    if (!result.validated) offset += residual;
  }
  result.interval_offset_rad = offset;
  for (const auto& run : result.runs) {
    if (!run.rejected.empty()) {
      result.warnings.push_back(std::to_string(run.rejected.size()) +
                                " position(s) fell outside the others' intervals and were left "
                                "out; if many do, the noise is larger than stated");
    }
  }
  return result;
}

}  // namespace cellmetry

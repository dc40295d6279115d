// Cameras left out: what a cell says without a camera.
//
// A user without a measured truth can still ask whether the cameras agree: identify the cell
// again without each camera in turn and compare every base and tool with the all-camera answer.
// A camera whose own error (a principal point, a lens, a board it sees at a bad angle) pulls the
// answer shows as a difference beyond what the two answers' uncertainties allow.
//
// The sigma of a difference, per coordinate. The fit without camera c uses a subset of the
// all-camera fit's rows (and the same priors), so for the data's part the difference's variance
// is the difference of the two variances (Hausman 1978: the fuller estimate is the more
// efficient one under the model):
//   var_stat(d) = max(stat_c^2 - stat^2, model_c^2 - model^2),
// the second term (the unscaled model covariances, whose difference cannot be negative) a floor
// where the cluster-robust parts do not order. The uncertain inputs are shared: each input's
// error moves both answers, so its part is the difference of its two effects (Uncertainty::
// input_effect), summed over inputs in quadrature. The systematic part (the jackknife between
// cameras) is what this check measures and is not in the sigma.
#pragma once

#include <array>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// One frame (a robot's base, a tool) without a camera, against the all-camera answer.
struct FrameDifference {
  std::string frame;
  // Free in both answers and informed by the camera left out (its difference's sigma not
  // negligible against the coordinate's own): x y z rx ry rz.
  std::array<bool, 6> compared{};
  Eigen::Matrix<double, 6, 1> difference =
      Eigen::Matrix<double, 6, 1>::Zero();  // without -
                                            // with all, mm and rad (about the parent's axes)
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();  // of the difference
};

struct CameraLeftOut {
  std::string camera;
  std::vector<FrameDifference> frames;  // each robot's base, then its tools
  double worst_sigmas = 0.0;            // the largest |difference| / sigma over every coordinate
  std::string worst;                    // its name, "ur3.base.y"
  std::string error;                    // the cell without the camera could not be identified
  // |difference| / sigma beyond which it is flagged: 3 sigma's two-sided 0.27 % shared over
  // every coordinate the run compares (Bonferroni), so that a run of ten robots and eight
  // cameras (480 coordinates) flags a camera by chance as rarely as one coordinate at 3 sigma
  // would: 3.9 sigma for exp_a's 27, 4.5 for 480; never below 3.
  double flag_sigmas = 3.0;
  bool flagged() const { return error.empty() && worst_sigmas > flag_sigmas; }
};

// The flag threshold (CameraLeftOut::flag_sigmas) for `compared` coordinates in all.
double CameraLeftOutFlagSigmas(int compared);

// `recording` without the observations of `cameras` and without them in its camera list.
Recording WithoutCameras(const Recording& recording, const std::set<std::string>& cameras);

// The cameras `spec` does not use (`cameras: {<camera>: {use: false}}`).
std::set<std::string> UnusedCameras(const WorkcellProblem& spec);

}  // namespace cellmetry

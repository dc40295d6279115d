// The names of a WorkcellProblem's choices (workcell_problem.h), as jobs and results spell them.
#include "cellmetry/cell/workcell_problem.h"

namespace cellmetry {

std::string CameraModelName(CameraModel model) {
  return model == CameraModel::kStaticCameras ? "static_cameras" : "per_frame";
}

std::string ResidualFormName(ResidualForm form) {
  return form == ResidualForm::kCartesian ? "cartesian" : "joint_space";
}

}  // namespace cellmetry

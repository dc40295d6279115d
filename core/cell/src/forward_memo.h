// One joint reading's forward kinematics (and flange twists), shared by the residual blocks
// that read it (internal to the cell layer).
//
// Every camera's position and rotation blocks of one capture run the same chain at the same
// joints, and so do the repeated captures of one pose: on exp_a with its uncertain inputs free
// (the UR3's table) that is sixty forward kinematics with twists per pose where one will do.
// The blocks of a joint reading hold one memo; it keeps the last result with the parameter
// values it was made at and makes it again for any other values, so the answer is the same bits
// as computing it. Blocks of one reading may be evaluated on two threads at once: a mutex guards
// it (uncontended but at a range's boundary, and far cheaper than the chain).
#pragma once

#include <Eigen/Core>
#include <mutex>
#include <vector>

#include "cellmetry/model/robot_model.h"

namespace cellmetry {

class ForwardMemo {
 public:
  // `model` and `q` (model.num_joints() values) must outlive the memo.
  ForwardMemo(const RobotModel* model, const double* q) : model_(model), q_(q) {}

  // model->Forward, or with `twists` ForwardWithTwists, at (q, params). False where the model
  // has no pose.
  bool Forward(const double* params, Pose* T_base_flange,
               Eigen::Matrix<double, 6, Eigen::Dynamic>* twists);

 private:
  const RobotModel* model_;
  const double* q_;
  std::mutex mutex_;
  bool made_ = false, with_twists_ = false, ok_ = false;
  std::vector<double> params_;
  Pose T_base_flange_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> twists_;
};

}  // namespace cellmetry

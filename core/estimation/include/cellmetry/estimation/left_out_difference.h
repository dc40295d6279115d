// How far an estimate without one group of rows (a camera's) may honestly differ from the
// estimate with all of them.
//
// Both estimates are linear in the residuals to first order at the full answer:
//
//   theta      - theta*  = -B   sum_k s_k,            B   = (J^T J)^-1
//   theta_{-g} - theta*  = -B_g sum_k (s_k - s_kg),   B_g = (J^T J - J_g^T J_g + P_g)^-1
//
// with s_k = J_k^T r_k the score of cluster k (a pose: every camera's view of it), s_kg its
// part from group g's rows, and P_g the information of the priors the fit without g adds (a
// gauge that only it has). Their difference d = theta_{-g} - theta is then a sum of per-cluster
// terms d_k = B s_k - B_g (s_k - s_kg), whose variance is taken as the fit's own statistical
// part is (robust_covariance.h): the sandwich over clusters with the Bartlett-weighted cross
// products of the `lag` neighbouring clusters, and no less than the model's
// scale * (B_g - B), the difference of two nested estimates' covariances (Hausman 1978). A
// prior only the fit without g has adds B_g P_g B_g: the value it gives is drawn from it.
//
// Columns the rows without g cannot determine (FindDegenerateColumns at `tolerance`: the left-out
// camera's own pose and intrinsics) are NaN.
#pragma once

#include <map>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/problem.h"

namespace cellmetry {

struct LeftOutGroup {
  int group = 0;                            // in group_of_block
  std::map<int, double> added_prior_sigma;  // free column -> sigma of a prior only it has
};

// Per entry of `left_out`, the variance of each free parameter's difference (its unit squared).
// `at` is the full fit's linearization with its Jacobian; `group_of_block` and
// `cluster_of_block` give each residual block's group (a camera; negative: none) and cluster (a
// pose in capture order; negative: a cluster of its own, after the others); `full` is the full
// fit's uncertainty (its scale and correlated_poses; B is made from `at`).
std::vector<Eigen::VectorXd> LeftOutDifferenceVariance(
    const Problem& problem, const Linearization& at, const std::vector<int>& group_of_block,
    const std::vector<int>& cluster_of_block, const Uncertainty& full,
    const std::vector<LeftOutGroup>& left_out, double tolerance);

}  // namespace cellmetry

// Uncertainty that holds up when the errors are not independent.
//
// The covariance ComputeUncertainty gives, (J^T J)^-1 scaled by the reduced chi-square, assumes
// every residual row is an independent measurement. A real camera's errors are not: what it gets
// wrong about one view (a board seen at an angle, a lens error at that place in the image) is
// shared by every row of that view, and by every view of that camera. Two estimates that do not
// assume it:
//
//   ClusterRobustCovariance   the "sandwich" (Liang & Zeger 1986; Cameron & Miller 2015, eq. 11):
//                               V = B (sum_g J_g^T r_g r_g^T J_g) B * G / (G - 1),
//                             B = (J^T J)^-1, the sum over clusters g of rows that may share
//                             errors (a pose: every camera's view of it), G clusters. With
//                             independent rows it equals the model covariance on average;
//   JackknifeSpread           the spread of estimates that each leave one group out (a camera),
//                               var = (n - 1) / n sum_k (theta_k - mean)^2   (Efron 1982),
//                             which sees errors shared by everything one camera measured;
//   LinearizedJackknife       those leave-one-out estimates as one Gauss-Newton step from the
//                             full answer instead of a refit each (Efron 1982, ch. 6: the
//                             "infinitesimal" form): exact for a linear model, off by terms
//                             second order in the deviation otherwise, and free of refits.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/problem.h"

namespace cellmetry {

// `cluster_of_block[b]` for each residual block of `problem` (its block order); blocks with a
// negative cluster (priors) are clusters of their own. `at` is the problem's linearization and
// `model` ComputeUncertainty's answer from it. Returns the covariance over the free parameters,
// in their units.
Eigen::MatrixXd ClusterRobustCovariance(const Problem& problem, const Linearization& at,
                                        const std::vector<int>& cluster_of_block,
                                        const Uncertainty& model);

// The same with the clusters in a sequence (their ids in capture order: a pose each) whose
// errors may be shared by neighbours: a camera sweeping over a board sees it at nearly the same
// angle at the next pose, and its pose estimator errs nearly the same way there. `serial`: the
// meat also sums the neighbours' cross products, weighted by the Bartlett kernel
// 1 - l / (L + 1) up to lag L (Newey & West 1987), L chosen from the data by Andrews' AR(1)
// plug-in (Andrews 1991, eq. 6.2; BartlettBandwidth). Independent clusters give L near 0 and
// the plain sandwich. Without `serial`, the plain sandwich.
struct ClusterRobust {
  Eigen::MatrixXd covariance;  // over the free parameters, in their units (empty: no answer)
  int lag = 0;                 // L: how many neighbours' errors were taken as shared
};
ClusterRobust SerialClusterRobustCovariance(const Problem& problem, const Linearization& at,
                                            const std::vector<int>& cluster_of_block,
                                            const Uncertainty& model, bool serial = true);

// Andrews' (1991) automatic bandwidth of the Bartlett kernel from AR(1) fits to each series:
// L = 1.1447 (alpha(1) T)^(1/3), alpha(1) = sum 4 rho^2 s^4 / ((1 - rho)^6 (1 + rho)^2) /
// sum s^4 / (1 - rho)^4, with each AR(1)'s rho (kept within +-0.97) and innovation variance
// s^2, T the series' length; at most T / 4. Series shorter than 3 are passed over.
int BartlettBandwidth(const std::vector<Eigen::VectorXd>& series);

// The jackknife variance of each entry over the leave-one-out estimates (one vector per left-out
// group; NaN where that estimate has no value for the entry, which then counts only the groups
// that have one), and how many groups each counted.
struct Jackknife {
  Eigen::VectorXd variance;
  Eigen::VectorXi groups;
};
Jackknife JackknifeSpread(const std::vector<Eigen::VectorXd>& values);

// For each group g = 0, 1, ... of residual blocks (`group_of_block`, block order;
// negative: in no group, always kept), the deviation d from the answer `at` that minimizes
// |J_{-g} d + r_{-g}|^2 without g's rows. Columns the remaining rows cannot determine
// (FindDegenerateColumns at `tolerance`: a left-out camera's own pose, or what only it saw) are
// NaN there, as a refit would not have them.
std::vector<Eigen::VectorXd> LinearizedJackknife(const Problem& problem, const Linearization& at,
                                                 const std::vector<int>& group_of_block,
                                                 double tolerance);

// Splits `u`'s sigma into its parts (Uncertainty) and sets the total: `cluster` from
// ClusterRobustCovariance (empty: none), `jackknife` (empty: none). A systematic part is claimed
// only where the jackknife's variance exceeds the statistical one beyond chance: with g groups,
// var_jack / var_stat is about chi-square(g - 1) / (g - 1) when nothing is shared, so it must
// pass that distribution's `quantile` (default 0.99: one clean parameter in a hundred gets a
// systematic part by chance).
void CombineUncertainty(const Eigen::MatrixXd& cluster, const Jackknife& jackknife, Uncertainty* u,
                        double quantile = 0.99);

}  // namespace cellmetry

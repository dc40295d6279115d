// Gross outliers: observations a fit cannot have come from.
//
// A mis-detected marker, a board seen through a reflection, a capture taken while the arm still
// moved: one such observation pulls a least-squares fit by as much as its error, and the result
// says nothing. So each residual row (one observation's position, or its rotation) is tested:
//
//   statistic  q = |r|^2, the row's whitened squared norm (r = (prediction - measurement) / sigma,
//              3 dof), divided by the robust scale of its own group (the rows of one camera,
//              target and kind: a world board's repeated views scatter far less than a carried
//              board's):  s^2 = median(q) / median(chi-square, 3 dof)  (0 for groups of < 10 rows:
//              not tested)
//   outlier    q / s^2 > max(chi-square quantile (1 - alpha / N, 3 dof), 3 * 10^2),  alpha 0.01
//
// The first is a Bonferroni test over the N rows (on clean Gaussian data the chance of flagging
// any row is alpha); the second asks for a gross error, ten robust standard deviations on
// every axis together, because real recordings' residuals are heavy-tailed where the model is
// short (the chance test alone left out 27 % of sim_b's observations). The median keeps a
// recording whose residuals all exceed the floor from flagging half its rows, and is barely
// moved by 10 % of gross errors.
//
// Where the rows come from (IdentifyWorkcell): first a robust fit (robust_first_fit.h, a
// Cauchy loss at 3 robust sigma, the scale measured again at each answer), which 10 % of gross
// errors do not pull, so their rows stand out; the observations it flags are left out, and the
// cell is fitted by plain least squares without them, so sigma stays the Gaussian one. The test
// then runs on that plain fit's rows too, twice at most (what the first outliers masked). On
// clean data nothing is flagged and the answer is the plain fit's, exactly.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// (Outlier, the result's record of one, is in workcell_result.h.)

// Each row's group scale s^2 (above; 0 where the group has too few rows to have one).
std::vector<double> RobustScales(const std::vector<ResidualRow>& rows);

// The rows of `rows` (about observations of `recording`) that fail the test at `alpha`.
std::vector<Outlier> FindOutliers(const std::vector<ResidualRow>& rows, const Recording& recording,
                                  double alpha = 0.01);

// The same two over an assembled workcell's measurement blocks (its problem's priors are not
// tested) and its problem's whitened residuals `whitened` (Problem::EvaluateSparse's, or a
// linearization's), without making the result's rows, which the robust first fit
// (robust_first_fit.h) would otherwise make again at each of its reads. Scales in the problem's
// block order.
std::vector<double> RobustScales(const AssembledWorkcell& assembled,
                                 const Eigen::VectorXd& whitened);
std::vector<Outlier> FindOutliers(const AssembledWorkcell& assembled,
                                  const Eigen::VectorXd& whitened, const Recording& recording,
                                  double alpha = 0.01);

// `recording` without the observations `outliers` name (by line, else by sample, camera, target).
Recording WithoutOutliers(const Recording& recording, const std::vector<Outlier>& outliers);

// Residual rows fitted on `kept` (WithoutOutliers of `original`, possibly repeated) numbered by
// their observation's index in `original`, as residuals.csv promises: kept's observations are
// original's in the same order with some left out.
void NumberByOriginal(const Recording& original, const Recording& kept,
                      std::vector<ResidualRow>* rows);

// outliers.csv: line,sample,camera,target,kind,score,threshold.
std::string OutliersCsv(const std::vector<Outlier>& outliers);

}  // namespace cellmetry

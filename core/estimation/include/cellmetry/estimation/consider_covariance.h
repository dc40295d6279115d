// What an estimate inherits from inputs held at stated values that are themselves uncertain.
//
// A fit holds some inputs at values it is given: a robot's nominal kinematic table, the printed
// size of a board, a camera's factory focal length. None of them is exact, and no resampling of
// the data sees their error: every observation shares it. Metrology treats them as type-B
// uncertainties (GUM, JCGM 100:2008, sec. 4.3): their standard uncertainty, stated by the user,
// propagates through the estimate's sensitivity to them. For a least-squares estimate that
// sensitivity is the normal equations' response to a shift dc of the held inputs,
//
//   d theta = G dc,   G = -(J_t^T J_t)^-1 J_t^T J_c,   Sigma_inputs = G diag(sigma_c^2) G^T,
//
// the "consider" covariance of orbit determination (Tapley, Schutz & Born 2004, Statistical
// Orbit Determination, ch. 6), with J_t the whitened Jacobian's columns of the estimated
// parameters and J_c those of the held inputs, both at the answer. To first order it is exact:
// refitting with an input moved by dc moves the estimate by G dc
// (tests/test_consider_covariance.cc checks that).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/estimation/problem.h"

namespace cellmetry {

// `augmented` holds the estimated parameters and the uncertain inputs, all free, at the answer,
// without a robust loss; `at` is its normal equations there (J^T J holds J_t^T J_c: summed block
// by block, no Jacobian is stored), null where they could not be evaluated (an InputError).
// `estimated` names the estimate's parameters (the order of the result) and `bread` is
// (J_t^T J_t)^-1 over them (ComputeUncertainty's covariance over its scale; zero rows and
// columns for what the data cannot determine). `input_sigma` maps each uncertain input's
// parameter name to its standard uncertainty, in its unit; other free columns of `augmented`
// are ignored. Returns G (estimated x inputs, in input_sigma's order) in `sensitivity` if not
// null, and Sigma_inputs.
Eigen::MatrixXd ConsiderCovariance(const Problem& augmented, const NormalEquations* at,
                                   const std::vector<std::string>& estimated,
                                   const Eigen::MatrixXd& bread,
                                   const std::map<std::string, double>& input_sigma,
                                   Eigen::MatrixXd* sensitivity = nullptr);

}  // namespace cellmetry

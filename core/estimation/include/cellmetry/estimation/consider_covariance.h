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

// J_t^T J_c read off `at`, the normal equations of `augmented` at the answer (summed block by
// block: no Jacobian is stored). `augmented` holds the estimated parameters and the uncertain
// inputs, all free, at the answer, without a robust loss. Rows follow `estimated` (the
// estimate's parameter names, the order of the result), columns `inputs` (the uncertain inputs'
// parameter names); zero where a name is not free in `augmented`.
Eigen::MatrixXd ConsiderCrossProduct(const Problem& augmented, const NormalEquations& at,
                                     const std::vector<std::string>& estimated,
                                     const std::vector<std::string>& inputs);

// Sigma_inputs (estimated x estimated) from `cross` = J_t^T J_c (ConsiderCrossProduct), `bread`
// = (J_t^T J_t)^-1 over the estimated parameters (ComputeUncertainty's covariance over its
// scale; zero rows and columns for what the data cannot determine) and each input's standard
// uncertainty `input_sigma`, in its unit (cross's column order). Returns G (estimated x inputs)
// in `sensitivity` if not null; zero where nothing is estimated or there are no inputs, and
// std::invalid_argument where `cross` is not estimated x inputs.
Eigen::MatrixXd ConsiderCovariance(const Eigen::MatrixXd& cross, const Eigen::MatrixXd& bread,
                                   const Eigen::VectorXd& input_sigma,
                                   Eigen::MatrixXd* sensitivity = nullptr);

}  // namespace cellmetry

// How much to trust an answer: identifiability, covariance, correlations.
//
// All of it is computed from the whitened Jacobian J of a Problem at its current values, the
// same way whichever solver produced them.
//
//  - Identifiability: columns of J are scaled to unit norm (so mm and rad compare), and the
//    singular values of the scaled J are inspected. A singular value below `tolerance` times the
//    largest marks a direction the data cannot determine; the parameter with the largest share
//    of that direction is reported and should be held at its nominal value (then repeat).
//    Where the direction moves a parameter whose physics has a plausible size (an effect's
//    Parameter::plausible), that parameter is given a prior instead, and the direction is
//    determined by it with an honest sigma rather than by an arbitrary hold (a gauge prior).
//  - Covariance: (J^T J)^-1 from the SVD of the scaled J, times a scale factor: the reduced
//    chi-square when it exceeds 1 (the model explains the data worse than the stated noise, so
//    the stated noise is too optimistic), else 1.
#pragma once

#include <Eigen/Core>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

// A free parameter that moves with an unidentifiable one along the direction the data cannot
// see: `ratio` is its move per unit move of the unidentifiable one, in parameter units.
struct GaugePartner {
  std::string name;
  double ratio = 0.0;
};

// The prior a gauge gets on a parameter whose physics has a plausible size: mean zero (an
// effect at zero is no effect) and sigma half that size, so that the plausible size is a two-
// sigma bound.
double GaugePriorSigma(const Parameter& p);

struct UnidentifiableParameter {
  std::string name;
  std::string reason;  // e.g. "no measurement depends on it" / "moves together with a, b"
  // Along the undetermined direction. What the data does determine is, for each partner,
  // partner - ratio * this: held at its nominal value, this parameter's error is carried by
  // its partners' estimates, and `cellmetry evaluate` scores those combinations.
  std::vector<GaugePartner> moves_with;
  // > 0: not held. The direction is determined by a prior on this parameter (GaugePriorSigma,
  // in its unit), which the covariance carries into every partner's sigma.
  double prior_sigma = 0.0;
  // Non-empty: held by convention (Parameter::convention, what it puts where): its partners are
  // given relative to it, not undetermined.
  std::string convention;
};

// What a solve holds at its starting values (`held`) and which parameters it gives a gauge
// prior (`prior_sigma`, name -> sigma), by "<block>.<parameter>" name.
struct HeldParameters {
  std::set<std::string> held;
  std::map<std::string, double> prior_sigma;
  HeldParameters() = default;
  HeldParameters(std::set<std::string> names) : held(std::move(names)) {}  // NOLINT: implicit
};
HeldParameters HeldOf(const std::vector<UnidentifiableParameter>& found);

// Free parameters that the data cannot determine, in the order they should be held. With `at`,
// also the linearization the verdict was made on (residuals, Jacobian, its R factor); without,
// J is not stored where its Gram rows stand for it (Problem::HasGramRows).
std::vector<UnidentifiableParameter> FindUnidentifiable(Problem& problem, double tolerance,
                                                        Linearization* at = nullptr);

// The same on columns of a Jacobian given by its R factor and column norms (r_factor.h): first
// the columns no row depends on (norm <= 1e-12 of the largest), then one at a time the column
// with the largest share of the smallest scaled singular direction while that singular value is
// below `tolerance` times the largest, with the columns sharing that direction (|v| > 0.1).
// `convention` (empty, or one flag per column: Parameter::convention) puts a convention column
// first: where one has a share of at least 0.1 in the space of every degenerate direction, it is
// held (the one with the largest share), along the direction of that space it moves most.
struct DegenerateColumn {
  int column = 0;
  bool no_data = false;
  std::vector<int> partners;
  std::vector<double> partner_ratios;  // each partner's move per unit move of `column`
  std::vector<double> partner_shares;  // |v| of each partner in the scaled singular vector
};
std::vector<DegenerateColumn> FindDegenerateColumns(const Eigen::MatrixXd& R,
                                                    const Eigen::VectorXd& norms, double tolerance,
                                                    const std::vector<bool>& convention = {});

// Fixes the free parameters called "<block>.<parameter>" in `held.held`, gives those in
// `held.prior_sigma` their gauge prior, and rebuilds the problem.
void HoldParameters(Problem* problem, const HeldParameters& held);

struct IdentifiedSolve {
  SolverSummary summary;
  // Held at their starting values, or (prior_sigma > 0) determined by a gauge prior.
  std::vector<UnidentifiableParameter> unidentifiable;
  // The linearization at the answer that the last check was made on, when that check held
  // nothing more (else not valid): the covariance needs exactly it, so it is not evaluated and
  // factored a second time.
  Linearization at_answer;
};

// Holds `held` and whatever the data cannot determine, solves, and checks again at the answer
// (a direction can become degenerate only there, e.g. at a singular configuration); if it finds
// more, holds them and solves again. A direction that moves a parameter with a plausible size
// gets a gauge prior on it instead of a hold (the one with the largest share of the direction).
// `warm_start`: the values are already a neighbouring problem's answer with `held` held (a
// cross-validation fold), so the check before the solve is skipped and only the one at the
// answer made. Every solve is checked where it ends: a
// non-finite parameter or cost throws InputError ("the fit diverged").
IdentifiedSolve SolveHoldingUnidentifiable(Problem* problem, double tolerance, HeldParameters held,
                                           const SolverMaker& make_solver, bool warm_start = false);

struct Uncertainty {
  std::vector<std::string> names;  // free parameters, in Problem order
  Eigen::VectorXd sigma;           // 1-sigma, in each parameter's unit: the total (below)
  // Its parts (robust_covariance.h, consider_covariance.h). statistical = the larger of the
  // chi-square-scaled model's and the cluster-robust sigma; systematic = what errors shared by a
  // whole camera add (the camera jackknife's spread beyond the statistical); inputs = what the
  // uncertainty of inputs held at stated values adds (a nominal kinematic table, a board's
  // printed size: type B); sigma^2 = statistical^2 + systematic^2 + inputs^2.
  // Empty where not computed: sigma is then the model's.
  Eigen::VectorXd sigma_model;
  Eigen::VectorXd sigma_cluster;
  Eigen::VectorXd sigma_statistical;
  Eigen::VectorXd sigma_systematic;
  Eigen::VectorXd sigma_inputs;
  // Each uncertain input's share of the inputs part: the move of every free parameter for a one-
  // sigma error of that input (columns: `input_names`; G diag(sigma), consider_covariance.h).
  // Two fits sharing an input err together: their difference's inputs part is the difference
  // of these columns.
  Eigen::MatrixXd input_effect;
  std::vector<std::string> input_names;
  // How many neighbouring poses (in capture order) the statistical part takes as sharing their
  // errors (SerialClusterRobustCovariance's lag); 0: each pose's errors its own.
  int correlated_poses = 0;
  Eigen::MatrixXd covariance;
  // (J^T J)^-1 of the fit's own whitened rows, priors included and unscaled: how the answer
  // moves with its rows, the "bread" of every sandwich (cluster-robust, consider).
  Eigen::MatrixXd inverse_information;
  Eigen::MatrixXd correlation;
  double chi2 = 0.0;  // |r|^2 of the whitened measurement residuals
  int dof = 0;        // residuals - free parameters
  double reduced_chi2 = 0.0;
  double scale = 1.0;             // factor applied to the measurements' part of the covariance
  double condition_number = 0.0;  // of the column-scaled Jacobian
  // Variance inflation factor per free parameter: how much larger its variance is than if every
  // other parameter were known, 1 / (1 - R^2) of its Jacobian column on the others. 1 =
  // independent; thousands = the data can barely tell it from a combination of the others.
  Eigen::VectorXd variance_inflation;
};

// From `at`, the problem's linearization at its current values (Linearize). Throws InputError
// when `at` is not valid: a fit that ends where the model cannot be evaluated has no uncertainty.
Uncertainty ComputeUncertainty(const Problem& problem, const Linearization& at);
Uncertainty ComputeUncertainty(Problem& problem);  // linearizes at the current values

// Free parameters the data determines only barely: identifiable in exact arithmetic, but with a
// variance inflation of at least `vif_threshold` (their sigma is sqrt(vif) times what it would be
// if the others were known), strongest first, each with the parameters it moves with.
struct WeakParameter {
  std::string name;
  double variance_inflation = 0.0;
  std::string partners;  // "a (0.99), b (-0.97)": |correlation| >= 0.9
};
std::vector<WeakParameter> WeaklyIdentified(const Uncertainty& uncertainty,
                                            double vif_threshold = 1e5);

struct CorrelatedPair {
  std::string a;
  std::string b;
  double correlation = 0.0;
};

// Pairs with |correlation| >= threshold, strongest first.
std::vector<CorrelatedPair> StrongCorrelations(const Uncertainty& uncertainty,
                                               double threshold = 0.9);

}  // namespace cellmetry

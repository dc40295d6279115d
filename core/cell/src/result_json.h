// JSON pieces shared by every result writer (internal to the core).
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

inline std::vector<double> Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A frame's translation (offset 0) or rotation (offset 3) sigma: null where the entry was held,
// so that no reader takes a held entry for one known perfectly.
inline nlohmann::json SigmaJson(const Eigen::Vector3d& sigma, const std::array<bool, 6>& held,
                                int offset) {
  nlohmann::json j = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    j.push_back(held[offset + i] ? nlohmann::json(nullptr) : nlohmann::json(sigma[i]));
  }
  return j;
}

inline nlohmann::json RmsJson(const ResidualRms& rms) {
  return {{"count", rms.count},
          {"x", rms.axis.x()},
          {"y", rms.axis.y()},
          {"depth", rms.axis.z()},
          {"norm", rms.norm}};
}

inline nlohmann::json SolverJson(const SolverSummary& s) {
  return {{"name", s.solver},
          {"iterations", s.iterations},
          {"evaluations", s.evaluations},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost},
          {"converged", s.converged},
          {"stop_reason", s.stop_reason},
          {"time_s", s.time_s}};
}

// Fit statistics, free parameters with sigma, correlations, unidentifiable parameters.
inline void AddUncertaintyJson(const Uncertainty& u,
                               const std::vector<UnidentifiableParameter>& unidentifiable,
                               const std::vector<CorrelatedPair>& strong, nlohmann::json* j) {
  (*j)["unidentifiable"] = nlohmann::json::array();
  for (const auto& p : unidentifiable) {
    nlohmann::json moves_with = nlohmann::json::array();
    for (const auto& partner : p.moves_with) {
      moves_with.push_back({{"name", partner.name}, {"ratio", partner.ratio}});
    }
    (*j)["unidentifiable"].push_back(
        {{"name", p.name},
         {"reason", p.reason},
         {"moves_with", moves_with},
         {"determined_by", p.prior_sigma > 0.0     ? "prior"
                           : !p.convention.empty() ? "convention"
                                                   : "hold"},
         {"convention",
          p.convention.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.convention)},
         {"prior_sigma", p.prior_sigma > 0.0 ? nlohmann::json(p.prior_sigma) : nullptr}});
  }
  (*j)["fit"] = {{"chi2", u.chi2},
                 {"dof", u.dof},
                 {"reduced_chi2", u.reduced_chi2},
                 {"covariance_scale", u.scale},
                 {"correlated_poses", u.correlated_poses},
                 {"condition_number", u.condition_number}};
  (*j)["free_parameters"] = u.names;
  (*j)["sigma"] = std::vector<double>(u.sigma.data(), u.sigma.data() + u.sigma.size());
  std::vector<std::vector<double>> correlation(u.correlation.rows());
  for (Eigen::Index i = 0; i < u.correlation.rows(); ++i) {
    for (Eigen::Index k = 0; k < u.correlation.cols(); ++k) {
      correlation[i].push_back(u.correlation(i, k));
    }
  }
  (*j)["correlation"] = correlation;
  (*j)["strong_correlations"] = nlohmann::json::array();
  for (const auto& c : strong) {
    (*j)["strong_correlations"].push_back({{"a", c.a}, {"b", c.b}, {"correlation", c.correlation}});
  }
}

}  // namespace cellmetry

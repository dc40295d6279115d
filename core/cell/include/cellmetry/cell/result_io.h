// Writing a WorkcellResult.
//
//   result.yaml     frames (xyz mm, rvec rad) and model parameters, ready to paste into configs
//   result.json     everything: parameters with sigma, correlations, residual statistics,
//                   held-out RMS, noise floor, solver summary, warnings
//   residuals.csv   one row per measurement: prediction - measurement in camera axes
//
// WriteWorkcellResult writes all three into `folder` atomically (whole or not at all).
// WorkcellSummary is the short text printed on the terminal.
#pragma once

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {

std::string WorkcellResultYaml(const WorkcellResult& result);
nlohmann::json WorkcellResultJson(const WorkcellResult& result);
std::string WorkcellResidualsCsv(const WorkcellResult& result);
// `extra`, when given, writes further files into the staged folder (its path) before the commit,
// so that they are part of the same whole-or-absent output (the command's report.html).
void WriteWorkcellResult(const WorkcellResult& result, const std::string& folder,
                         const std::function<void(const std::string& staging)>& extra = {});

std::string WorkcellSummary(const WorkcellResult& result);

}  // namespace cellmetry

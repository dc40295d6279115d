// PrepareFitInputs (fit_once.h): pairing and closed-form start beside the repeat spread.
#include <future>

#include "cellmetry/cell/workcell_initial.h"
#include "fit_once.h"

namespace cellmetry {

FitInputs PrepareFitInputs(const WorkcellProblem& spec, const Recording& recording) {
  std::future<NoiseModel> repeatability =
      std::async(std::launch::async, [&] { return EstimateRepeatability(recording); });
  FitInputs inputs;
  try {
    inputs.data = PrepareWorkcellData(spec, recording);
    inputs.start = InitialEstimate(spec, recording, inputs.data);
  } catch (...) {
    repeatability.wait();  // it reads `recording`
    throw;
  }
  inputs.repeatability = repeatability.get();
  inputs.noise = BuildNoiseModel(recording, spec.noise, inputs.repeatability);
  return inputs;
}

}  // namespace cellmetry

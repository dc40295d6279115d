// The rounds a diagnosis finished, kept in a Checkpoint (formats/checkpoint.h) as each ends, so
// that an interrupted `cellmetry diagnose` resumes at the round it was in.
//
// A round's record is what the next round starts from besides the model: the round's findings,
// the effect it accepted (if any), the candidates found untestable so far and the names no later
// round tests again. The model itself (the geometry and the accepted effects, fitted) is not
// kept: a resumed diagnosis refits it, one fit per accepted effect, exactly as the round did
// (DiagnoseWorkcell), and skips every finished round's scoring, refits and selection tests.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {

class Checkpoint;

struct RoundRecord {
  DiagnosisRound round;
  std::optional<AcceptedEffect> accepted;
  std::vector<CandidateFinding> untestable;  // every candidate found untestable so far
  std::vector<std::string> done;             // effect names no later round tests
};

class RoundLog {
 public:
  explicit RoundLog(Checkpoint* checkpoint);  // null: nothing kept, nothing resumed

  // Round `index` (from 1) as it finished before, or nothing.
  std::optional<RoundRecord> Finished(int index) const;
  void Keep(int index, const RoundRecord& record);

 private:
  Checkpoint* checkpoint_;
};

}  // namespace cellmetry

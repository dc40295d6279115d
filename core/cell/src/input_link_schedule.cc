// InputLinkSchedule (input_link_schedule.h): the threads beside a cell's identification.
#include "input_link_schedule.h"

#include <utility>

namespace cellmetry {

InputLinkSchedule& InputLinkSchedule::operator=(InputLinkSchedule&& other) noexcept {
  answer_ = std::move(other.answer_);  // first: a link of this schedule's ends before the wait
  link_ = std::move(other.link_);
  return *this;
}

bool InputLinkSchedule::Start(const WorkcellProblem& spec, const Recording& recording,
                              const WorkcellData& data, const NoiseModel& noise,
                              const WorkcellEstimate& start) {
  if (spec.uncertain_inputs.empty()) {  // nothing to link: no thread, no core taken
    link_ = std::async(std::launch::deferred, [] { return InputLink{}; });
    return false;
  }
  link_ = std::async(std::launch::async, [&spec, &recording, &data, &noise, start,
                                          answer = answer_.get_future()]() mutable {
    InputLinker linker(spec, recording, data, noise, start);
    return linker.LinkAt(answer.get());  // a broken promise throws here, and ends the link
  });
  return true;
}

void InputLinkSchedule::Answer(FitAnswer answer) { answer_.set_value(std::move(answer)); }

InputLink InputLinkSchedule::Take() { return link_.get(); }

void InputLinkSchedule::RunAlongside(const std::function<void()>& here,
                                     const std::function<void()>& alongside,
                                     bool alongside_on_another_core) {
  std::future<void> beside =
      std::async(alongside_on_another_core ? std::launch::async : std::launch::deferred, alongside);
  try {
    here();
    beside.get();  // rethrows what it threw
  } catch (...) {
    // `alongside` and the link read what the exception unwinds: finished before it goes on.
    if (beside.valid()) beside.wait();
    if (link_.valid()) link_.wait();
    throw;
  }
}

}  // namespace cellmetry

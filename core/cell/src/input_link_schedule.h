// InputLinkSchedule: the work a cell's identification runs on the machine's other core, and
// the one place that owns its threads, futures and promises (internal to the cell layer). The
// identification's stages (workcell.cc) call it and never see a future.
//
// Two kinds of work run beside the fit:
//
//   The uncertain inputs' link (input_uncertainty.h). Start() begins it on another thread: the
//   cell assembled again with its inputs free at the fit's start, which needs nothing but that
//   start, so it runs while this thread assembles and solves the fit. The thread then waits for
//   the answer Answer() gives, links at it (one pass of normal equations) and ends. Take()
//   waits for that and returns the link.
//
//   One function alongside another: RunAlongside() runs `alongside` (the residual statistics)
//   on another thread while this thread runs `here` (the covariance), and returns once both
//   have.
//
// Which core runs what. The link's thread takes the other core from Start() until the link is
// assembled, and again from Answer() until it is linked (assembled before the answer comes, it
// waits idle). Start() says whether there is such a thread (there is none when the job has no
// uncertain inputs: the link is then empty, made by Take()), so that a solve meanwhile leaves
// that core to it (LeavingOneCore). RunAlongside's `alongside` takes another core too, beside
// a link not yet done; told it has none (`alongside_on_another_core` false), it runs on this
// thread when `here` is done.
//
// What must outlive what. The link's thread reads the `spec`, `recording`, `data` and `noise`
// given to Start() by reference until it ends (`start` is copied): they must outlive the
// schedule, whose destructor waits for that thread, so declare the schedule after them. A
// schedule may be moved (a fit that started a link hands it to the identification that takes
// the fit); the thread then belongs to the schedule moved to, and what it reads must outlive
// that one. RunAlongside's functions end within the call.
//
// A broken promise. The answer the link waits for is a promise this schedule keeps. A schedule
// that goes before Answer() (the fit to be linked given up: an exception unwinds past it)
// breaks that promise first, which ends the link's thread (std::future_error, kept in the link,
// which no one takes then), and only then waits for the thread. A schedule started and never
// answered otherwise is a programming error: Take() would wait forever.
//
// Exceptions. What the link's thread throws (InputError where the model cannot be evaluated with
// the inputs free) is kept and rethrown by Take(). In RunAlongside, an exception of either
// function is rethrown only once `alongside` has finished (run now, if it was to run after
// `here`) and the link's thread has ended, because both read what the exception is about to
// unwind; where both throw, `here`'s goes on.
//
// Usage, in the order the identification's stages call it:
//
//   InputLinkSchedule input_link;                     // after what the link reads
//   const bool beside = input_link.Start(spec, recording, data, noise, start);
//   ... solve, leaving a core to the link where `beside` ...
//   input_link.Answer(AnswerOf(*fit.assembled));
//   input_link.RunAlongside(covariance, residual_statistics, /*alongside_on_another_core=*/true);
//   AddInputUncertainty(input_link.Take(), &uncertainty);
#pragma once

#include <functional>
#include <future>

#include "cellmetry/cell/workcell_assembly.h"
#include "input_uncertainty.h"

namespace cellmetry {

class InputLinkSchedule {
 public:
  InputLinkSchedule() = default;
  InputLinkSchedule(InputLinkSchedule&&) = default;
  // Breaks this schedule's own promise before it waits for its own link, as the destructor does.
  InputLinkSchedule& operator=(InputLinkSchedule&& other) noexcept;

  // Starts the link of `spec`'s uncertain inputs: assembled at `start` (the start the fit to be
  // linked is assembled at) from now on, on another thread, and linked at the answer Answer()
  // gives. Returns whether that thread runs (none where `spec` has no uncertain inputs). Once.
  bool Start(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
             const NoiseModel& noise, const WorkcellEstimate& start);

  // The fit's answer, which the link is made at. Once, before or after Start().
  void Answer(FitAnswer answer);

  // Whether Start() was called (on this schedule or on the one it was moved from).
  bool started() const { return link_.valid(); }

  // The link, once made; rethrows what its thread threw. Once, after Start() and Answer().
  InputLink Take();

  // Runs `here` on this thread and `alongside` meanwhile on another (or, when
  // `alongside_on_another_core` is false, on this thread after `here`), and returns once both
  // have; rethrows as the header says, after waiting for `alongside` and the link.
  void RunAlongside(const std::function<void()>& here, const std::function<void()>& alongside,
                    bool alongside_on_another_core);

 private:
  std::future<InputLink> link_;  // invalid until Start()
  // After the link, so that it goes first: a schedule given up before its answer breaks the
  // promise, which ends the link's thread, before the link's future waits for that thread.
  std::promise<FitAnswer> answer_;
};

}  // namespace cellmetry

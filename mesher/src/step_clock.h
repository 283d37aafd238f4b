#pragma once

#include <chrono>

#include "mesher/update_stats.h"

namespace terramesh::mesher::internal {

/// The steps of an update, as in the paper's Table II.
enum class Step { kIdle, kSteiner, kShrink, kInsertion, kRayTracing, kGrow };

/// Attributes wall-clock time to the step currently running. Steps nest: entering a step inside
/// another (e.g. untracing rays during an insertion) charges the inner step until it is left.
/// Timing only observes; it never changes what the pipeline does.
class StepClock {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StepClock(StepTimes& times) : times_(times), last_(Clock::now()) {}

  /// Switches to `step`, returning the step that was running.
  Step enter(Step step) {
    charge();
    const Step previous = current_;
    current_ = step;
    return previous;
  }

  /// Scoped step: restores the previous step on destruction.
  class Scope {
   public:
    Scope(StepClock& clock, Step step) : clock_(clock), previous_(clock.enter(step)) {}
    ~Scope() { clock_.enter(previous_); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StepClock& clock_;
    Step previous_;
  };

 private:
  void charge() {
    const Clock::time_point now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    switch (current_) {
      case Step::kSteiner: times_.steiner_s += seconds; break;
      case Step::kShrink: times_.shrink_s += seconds; break;
      case Step::kInsertion: times_.insertion_s += seconds; break;
      case Step::kRayTracing: times_.ray_tracing_s += seconds; break;
      case Step::kGrow: times_.grow_s += seconds; break;
      case Step::kIdle: break;
    }
  }

  StepTimes& times_;
  Clock::time_point last_;
  Step current_ = Step::kIdle;
};

}  // namespace terramesh::mesher::internal

#pragma once
// What the loop sections share: a sink that traces every published estimate (one step per output), a step clock, the
// loop's counters and the section's end traced after the last output, and static storage for an estimator too big
// for the stack.
#include <cstdint>
#include <new>
#include <utility>

#include "est/geometry/pose2.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/util/trace.hpp"

namespace est::selftest {

struct LoopTraceSink {
  Trace* d;
  std::uint32_t outputs;
  void operator()(const loop::LoopOutput& o) {
    d->step(outputs);
    d->add_u32("t_us", static_cast<std::uint32_t>(o.t_ns / 1000));
    d->add("x", o.estimate.mean.x);
    d->add("y", o.estimate.mean.y);
    d->add("theta", o.estimate.mean.theta);
    d->add_matrix("P", o.estimate.covariance);
    d->add_u32("status", o.status);
    ++outputs;
  }
};

struct LoopStepClock {  // the loop reads time only to time its steps
  loop::TimeNs t = 0;
  loop::TimeNs operator()() { return t += 1000; }
};

// A filter's count, named for the trace.
struct NamedCount {
  const char* name;
  std::uint32_t value;
};

// The published count and what the loop did with its inputs, traced as the step after the last output.
inline void add_loop_counters(Trace& d, std::uint32_t outputs, const loop::LoopCounters& c) {
  d.step(outputs);
  d.add_u32("outputs", outputs);
  d.add_u32("inputs", c.inputs);
  d.add_u32("predictions", c.predictions);
  d.add_u32("corrections", c.corrections);
  d.add_u32("rejected", c.rejected);
  d.add_u32("degenerate", c.degenerate);
  d.add_u32("too_old", c.too_old);
  d.add_u32("queue_full", c.queue_full);
  d.add_u32("unused", c.unused);
}

// The end of a per-model loop section: the loop's counters, what its filter counted, and the true pose.
template <typename... Counts>
inline void add_loop_end(Trace& d, std::uint32_t outputs, const loop::LoopCounters& c, const Pose2& truth,
                         Counts... filter_counts) {
  add_loop_counters(d, outputs, c);
  (d.add_u32(NamedCount(filter_counts).name, NamedCount(filter_counts).value), ...);
  d.add("truth_x", truth.x);
  d.add("truth_y", truth.y);
  d.add("truth_theta", truth.theta);
}

// A T in static storage (an MCL estimator's particle sets and KLD bins are ~60 KiB: more than a section should put
// on the board's stack), constructed afresh by each StaticInstance and destroyed with it, so every run of a section
// starts from the same state. One live instance per type.
template <typename T>
class StaticInstance {
 public:
  template <typename... Args>
  explicit StaticInstance(Args&&... args) : object_(new (storage()) T(std::forward<Args>(args)...)) {}
  ~StaticInstance() { object_->~T(); }
  StaticInstance(const StaticInstance&) = delete;
  StaticInstance& operator=(const StaticInstance&) = delete;
  T& operator*() const { return *object_; }
  T* operator->() const { return object_; }

 private:
  static void* storage() {
    alignas(T) static unsigned char bytes[sizeof(T)];
    return bytes;
  }
  T* object_;
};

}  // namespace est::selftest

#pragma once
// What the loop sections share: a sink that folds every published estimate into a digest, a step clock, the loop's
// counters and the section's end into a digest, and static storage for an estimator too big for the stack.
#include <cstdint>
#include <new>
#include <utility>

#include "est/geometry/pose2.hpp"
#include "est/loop/filter_loop.hpp"
#include "est/util/digest.hpp"

namespace est::selftest {

struct LoopDigestSink {
  Digest* d;
  std::uint32_t outputs;
  void operator()(const loop::LoopOutput& o) {
    d->add_u32(static_cast<std::uint32_t>(o.t_ns / 1000));
    d->add(o.estimate.mean.x);
    d->add(o.estimate.mean.y);
    d->add(o.estimate.mean.theta);
    d->add_matrix(o.estimate.covariance);
    d->add_u32(o.status);
    ++outputs;
  }
};

struct LoopStepClock {  // the loop reads time only to time its steps
  loop::TimeNs t = 0;
  loop::TimeNs operator()() { return t += 1000; }
};

// The published count and what the loop did with its inputs.
inline void add_loop_counters(Digest& d, std::uint32_t outputs, const loop::LoopCounters& c) {
  d.add_u32(outputs);
  d.add_u32(c.inputs);
  d.add_u32(c.predictions);
  d.add_u32(c.corrections);
  d.add_u32(c.rejected);
  d.add_u32(c.degenerate);
  d.add_u32(c.too_old);
  d.add_u32(c.queue_full);
  d.add_u32(c.unused);
}

// The end of a per-model loop section: the loop's counters, what its filter counted, and the true pose.
template <typename... Counts>
inline void add_loop_end(Digest& d, std::uint32_t outputs, const loop::LoopCounters& c, const Pose2& truth,
                         Counts... filter_counts) {
  add_loop_counters(d, outputs, c);
  (d.add_u32(filter_counts), ...);
  d.add(truth.x);
  d.add(truth.y);
  d.add(truth.theta);
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

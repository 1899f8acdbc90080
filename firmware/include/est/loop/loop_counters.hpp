#pragma once
// The loop's counters: what happened to the inputs, the steps, and per input kind (est/loop/input_kinds.hpp) the
// samples accepted and the outputs published while that kind was stale.
#include <cstdint>

#include "est/loop/input_kinds.hpp"

namespace est::loop {

struct KindCounters {
  std::uint32_t accepted = 0;  // queued
  std::uint32_t stale = 0;     // outputs published while no sample of this kind was within its staleness limit
};

struct LoopCounters {
  std::uint32_t inputs = 0;           // accepted into the queue
  std::uint32_t too_old = 0;          // dropped: older than what was already applied
  std::uint32_t queue_full = 0;       // dropped: no room
  std::uint32_t rejected = 0;         // refused by the estimator (bad control, bad scan)
  std::uint32_t predictions = 0;
  std::uint32_t corrections = 0;
  std::uint32_t degenerate = 0;
  std::uint32_t overruns = 0;         // steps over their deadline
  std::uint32_t unused = 0;           // dropped: a kind of input the configured filter does not use (not a fault)
  std::int64_t worst_step_ns = 0;     // longest step measured through the clock
  KindCounters kinds[kInputKindCount];

  const KindCounters& of(InputKind k) const { return kinds[index_of(k)]; }
  KindCounters& of(InputKind k) { return kinds[index_of(k)]; }
};

}  // namespace est::loop

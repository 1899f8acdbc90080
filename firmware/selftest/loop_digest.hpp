#pragma once
// What the loop sections share: a sink that folds every published estimate into a digest, and a step clock.
#include <cstdint>

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

}  // namespace est::selftest

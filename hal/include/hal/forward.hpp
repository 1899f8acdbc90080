#pragma once
// A port that shows every sample to a hook and hands it on to the next port of the same kind: what a node puts in
// its data path to stamp replay time, count what reaches the loop, or record it (one template for every sensor,
// instead of a hand-written forwarding class per use).
//
//   auto stamp = hal::forward<hal::SensorPort>(validated, [&](const auto& s) { clock.now = s.stamp_ns; });
#include <utility>

#include "hal/sensor_port.hpp"

namespace hal {

template <typename Port, typename Hook>
class Forward final : public PortImplementation<Forward<Port, Hook>, Port> {
 public:
  Forward(Port& next, Hook hook) : next_(&next), hook_(std::move(hook)) {}
  void set_next(Port& next) { next_ = &next; }

  template <typename Sample>
  void handle(const Sample& s) {
    hook_(s);
    next_->on(s);
  }

 private:
  Port* next_;
  Hook hook_;
};

template <typename Port, typename Hook>
Forward<Port, Hook> forward(Port& next, Hook hook) {
  return Forward<Port, Hook>(next, std::move(hook));
}

}  // namespace hal

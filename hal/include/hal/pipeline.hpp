#pragma once
// The estimator's pipeline, composed in one place for every program that runs the firmware (estimator_node, the
// simulator, the board image): raw samples in (from CAN frames through hal::can::CanInput, LCM messages through
// hal::lcm::LcmInputs, a board's drivers), the gate (hal::ValidatedInputs: every sample checked, every reject
// counted), an optional tap (a recorder or a counter: hal/forward.hpp), the adapter (hal::LoopPort), the firmware's
// filter loop and the estimate sink. The caller owns the estimator and the loop (their storage is the static
// configuration's, est/loop/configured_loop.hpp) and the clocks: `sample_clock` is what the gate judges staleness
// against, `step_clock` only times the steps.
#include <cstdint>

#include "est/loop/filter_loop.hpp"
#include "hal/estimate.hpp"
#include "hal/loop_port.hpp"
#include "hal/sensor_port.hpp"
#include "hal/time.hpp"
#include "hal/validated_inputs.hpp"

namespace hal {

template <typename Estimator>
class Pipeline {
 public:
  using Loop = est::loop::FilterLoop<Estimator>;

  Pipeline(Loop& loop, const InputLimits& limits, Clock& sample_clock, Clock& step_clock, EstimateSink& sink)
      : loop_(loop), port_(loop, step_clock, sink), gate_(limits, sample_clock, port_) {}
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Raw samples in.
  SensorPort& input() { return gate_; }
  // Checked samples go through `tap` first, which must hand them on to adapter().
  void set_tap(ValidatedSensorPort& tap) { gate_.set_output(tap); }
  ValidatedSensorPort& adapter() { return port_; }

  // The transports' status bits and their own rejects (CAN frames, LCM decoding), before the next input.
  void refresh(std::uint32_t transport_bits, std::uint32_t transport_rejects) {
    port_.set_transport_status(transport_bits);
    const std::uint64_t n = std::uint64_t{gate_.faults().total()} + transport_rejects;
    port_.set_upstream_rejects(n > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(n));
  }
  // Applies every queued input (end of a replay, shutdown).
  void flush() { port_.flush(); }

  const ValidatedInputs& gate() const { return gate_; }
  const LoopPort<Estimator>& port() const { return port_; }
  const Loop& loop() const { return loop_; }

 private:
  Loop& loop_;
  LoopPort<Estimator> port_;
  ValidatedInputs gate_;
};

}  // namespace hal

#pragma once
// The HAL-to-loop adapter: validated HAL samples in (it is the ValidatedSensorPort that hal::ValidatedInputs feeds),
// est::loop inputs out to a FilterLoop, and every LoopOutput on to an EstimateSink as a hal::Estimate whose status is
// the loop's bits | the transports' bits, with the count of inputs rejected anywhere on the way. Each sensor's
// to_loop_inputs (in its folder, hal/sensors/<sensor>/) converts its checked sample, once.
//
// The loop runs after every input handed to it, so its outputs are a function of the sequence of inputs alone: a
// node that records that sequence (with the stamps the loop used) and replays it gets the same estimates, bit for
// bit, whatever the transport's batching or the wall clock did. The clock times the steps (overruns), nothing else.
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "est/loop/filter_loop.hpp"
#include "hal/estimate.hpp"
#include "hal/fault.hpp"
#include "hal/sensor_port.hpp"
#include "hal/status_word.hpp"
#include "hal/time.hpp"

namespace hal {

// What the adapter itself refuses (the validators have passed the sample; the loop's shape does not fit it).
enum class LoopPortReject : std::uint8_t {
  none = 0,
  scan_too_large,  // more beams than the loop's scan slots hold
  kCount
};

inline const char* to_string(LoopPortReject r) {
  switch (r) {
    case LoopPortReject::none: return "none";
    case LoopPortReject::scan_too_large: return "scan_too_large";
    case LoopPortReject::kCount: break;
  }
  return "unknown";
}

using LoopPortRejectCounters = ReasonCounters<LoopPortReject>;

template <typename Estimator>
class LoopPort final : public PortImplementation<LoopPort<Estimator>, ValidatedSensorPort> {
 public:
  using Loop = est::loop::FilterLoop<Estimator>;

  LoopPort(Loop& loop, Clock& step_clock, EstimateSink& sink) : loop_(loop), clock_{step_clock}, publisher_{this, sink} {
    last_good_.covariance = Eigen::Matrix3f::Identity() * kUnknownVariance;
  }

  template <typename Checked>
  void handle(const Checked& sample) {
    if constexpr (std::is_same_v<Checked, RangeScanView>) {
      if (sample.count == 0u || sample.count > static_cast<std::size_t>(loop_.max_beams()))
        return rejects_.add(LoopPortReject::scan_too_large);
    }
    to_loop_inputs(sample, [this](const auto& in) { loop_.push(in); });
    loop_.run(clock_, publisher_);
  }

  // Applies every queued input (end of a replay, shutdown).
  void flush() { loop_.flush(clock_, publisher_); }

  // The transports' status bits (hal::status::kTransportMask) as of now: they stay in every estimate until the next
  // call; bits that were up at any call since the last estimate are in the next one too, so an event is never lost.
  void set_transport_status(std::uint32_t bits) {
    transport_now_ = bits & status::kTransportMask;
    transport_seen_ |= transport_now_;
  }
  // Inputs rejected upstream (validators, codecs, transports), in total since start; the adapter adds its own.
  void set_upstream_rejects(std::uint32_t total) { upstream_rejects_ = total; }

  std::uint32_t rejected_inputs() const {
    const std::uint64_t sum = std::uint64_t{upstream_rejects_} + rejects_.total();
    return sum > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(sum);
  }
  const LoopPortRejectCounters& rejects() const { return rejects_; }
  const est::loop::LoopCounters& loop_counters() const { return loop_.counters(); }
  std::uint32_t published() const { return published_; }
  std::uint32_t nonfinite_estimates() const { return nonfinite_; }

 private:
  static constexpr float kUnknownVariance = 1.0e6f;  // what a held pose claims before any good one: nothing

  struct StepClock {
    Clock& clock;
    TimeNs operator()() { return clock.now_ns(); }
  };
  struct Publisher {
    LoopPort* self;
    EstimateSink& sink;
    void operator()(const est::loop::LoopOutput& o) { self->publish(sink, o); }
  };

  static bool finite(const Estimate& e) {
    if (!__builtin_isfinite(e.pose.x) || !__builtin_isfinite(e.pose.y) || !__builtin_isfinite(e.pose.theta))
      return false;
    for (int i = 0; i < 9; ++i)
      if (!__builtin_isfinite(e.covariance.data()[i])) return false;
    return true;
  }

  void publish(EstimateSink& sink, const est::loop::LoopOutput& o) {
    Estimate e;
    e.stamp_ns = o.t_ns;
    e.pose = o.estimate.mean;
    e.covariance = o.estimate.covariance;
    e.rejected_inputs = rejected_inputs();
    e.status = (o.status & status::kLoopMask) | transport_now_ | transport_seen_;
    if (e.rejected_inputs != rejects_at_last_publish_) e.status |= status::kInputRejected;
    // An estimate is never NaN: a filter that produced one is reported degenerate and the last good pose is held.
    if (!finite(e)) {
      ++nonfinite_;
      e.pose = last_good_.pose;
      e.covariance = last_good_.covariance;
      e.status |= status::kFilterDegenerate;
    } else {
      last_good_ = e;
    }
    rejects_at_last_publish_ = e.rejected_inputs;
    transport_seen_ = 0;
    ++published_;
    sink.publish(e);
  }

  Loop& loop_;
  StepClock clock_;
  Publisher publisher_;
  LoopPortRejectCounters rejects_;
  std::uint32_t upstream_rejects_ = 0;
  std::uint32_t rejects_at_last_publish_ = 0;
  std::uint32_t transport_now_ = 0;
  std::uint32_t transport_seen_ = 0;
  std::uint32_t published_ = 0;
  std::uint32_t nonfinite_ = 0;
  Estimate last_good_;
};

}  // namespace hal

#pragma once
// The fixed-rate filter loop: inputs are queued in timestamp order and applied once they are older than the reorder
// window behind the newest input, so the outputs depend only on the inputs and their timestamps, never on when they
// arrived or on the wall clock. Prediction runs at a fixed period of input time (e.g. 100 Hz) with the encoder ticks
// accumulated since the last prediction; each scan is applied at its own time, after a prediction up to that time.
// The clock is read only to time each step (deadline overruns are counted, results never depend on it).
//
// Corrections (scans, landmark features) are applied at their own time after a prediction up to it; the output for
// a time is published once, after every input stamped with it.
//
// Estimator concept (adapters in est/loop/*_estimator.hpp; est/loop/configured_loop.hpp picks one):
//   static constexpr bool kUsesSteering, kUsesScans, kUsesLandmarks;
//   StepOutcome predict(const MotionInput&);
//   StepOutcome correct(const ScanInput&);       only if kUsesScans
//   StepOutcome correct(const LandmarkInput&);   only if kUsesLandmarks
//   PoseEstimate estimate() const;
// Inputs of a kind the estimator does not use (a lidar on the bus of an EKF on landmarks) are counted as unused and
// dropped when pushed: not a fault, no status bit.
#include <cstdint>

#include "est/filter/particle_estimate.hpp"
#include "est/loop/input_queue.hpp"
#include "est/loop/inputs.hpp"
#include "est/loop/status.hpp"

namespace est::loop {

struct LoopTiming {
  TimeNs predict_period_ns = 10000000;     // 100 Hz
  TimeNs reorder_window_ns = 20000000;     // inputs up to 20 ms late are still applied in order
  TimeNs encoder_timeout_ns = 100000000;   // staleness limits
  TimeNs steering_timeout_ns = 100000000;
  TimeNs scan_timeout_ns = 500000000;
  TimeNs landmark_timeout_ns = 1000000000;
  TimeNs step_deadline_ns = 5000000;       // budget of one predict or correct step, as measured by the clock
  std::uint32_t max_catch_up_predictions = 100;  // after a longer gap in the inputs, the loop jumps (one prediction)
};

struct MotionInput {
  float dt_s;
  std::int32_t left_ticks;   // increments since the previous prediction
  std::int32_t right_ticks;
  float steering_rad;        // the latest steering sample (sample and hold)
  bool steering_known;
};

enum class StepOutcome : std::uint8_t { applied, rejected, degenerate };

struct LoopOutput {
  TimeNs t_ns;
  PoseEstimate estimate;
  std::uint32_t status;  // est::loop::status bits
  const LoopCounters* counters;
};

template <typename Estimator, std::uint32_t QueueCapacity, std::int32_t KMax, std::uint32_t ScanSlots = 2>
class FilterLoop {
 public:
  FilterLoop(Estimator& estimator, const LoopTiming& timing) : est_(estimator), timing_(timing) {}

  // Queue an input. False (and counted) when it is older than what was already applied, or there is no room.
  template <typename Input>
  bool push(const Input& in) {
    if (!uses(in)) {
      ++counters_.unused;
      return false;
    }
    if (applied_any_ && in.t_ns < applied_t_) {
      ++counters_.too_old;
      sticky_ |= status::kInputTooOld;
      return false;
    }
    if (!queue_.push(in)) {
      ++counters_.queue_full;
      sticky_ |= status::kQueueFull;
      return false;
    }
    ++counters_.inputs;
    if (!seen_any_ || in.t_ns > newest_t_) newest_t_ = in.t_ns;
    seen_any_ = true;
    return true;
  }

  // Applies every queued input older than the newest input minus the reorder window. Bounded by the queue size.
  template <typename Clock, typename Sink>
  void run(Clock& clock, Sink& sink) {
    while (!queue_.empty() && queue_.front_time() <= newest_t_ - timing_.reorder_window_ns) apply_front(clock, sink);
  }

  // Applies everything queued (end of a replay, or shutdown).
  template <typename Clock, typename Sink>
  void flush(Clock& clock, Sink& sink) {
    while (!queue_.empty()) apply_front(clock, sink);
  }

  const LoopCounters& counters() const { return counters_; }
  std::uint32_t pending() const { return queue_.size(); }

 private:
  template <typename Clock, typename Sink>
  void apply_front(Clock& clock, Sink& sink) {
    const QueuedInput q = queue_.front();
    const TimeNs t = q.t_ns;
    if (!applied_any_) {
      applied_any_ = true;
      last_predict_t_ = t;
      next_predict_t_ = t + timing_.predict_period_ns;
      ticks_until_t_ = t;
    }
    // Predictions strictly before t: an increment stamped t is motion up to t, so it belongs in a prediction at t.
    advance_predictions(clock, sink, t, false);
    applied_t_ = t;
    switch (q.kind) {
      case InputKind::wheel_ticks:
        pending_left_ += q.ticks.left_ticks;
        pending_right_ += q.ticks.right_ticks;
        last_encoder_t_ = t;
        ticks_until_t_ = t;
        have_encoder_ = true;
        queue_.pop();
        break;
      case InputKind::steering:
        steering_rad_ = q.steering.angle_rad;
        last_steering_t_ = t;
        have_steering_ = true;
        queue_.pop();
        break;
      case InputKind::scan:
        if constexpr (Estimator::kUsesScans) {
          correct_at(clock, t, queue_.scan(q));
          last_scan_t_ = t;
          have_scan_ = true;
        }
        queue_.pop();
        break;
      case InputKind::landmark:
        if constexpr (Estimator::kUsesLandmarks) {
          correct_at(clock, t, q.landmark);
          last_landmark_t_ = t;
          have_landmark_ = true;
        }
        queue_.pop();
        break;
    }
    // The output at t and the prediction at t itself wait while more inputs stamped t are queued.
    if (queue_.empty() || queue_.front_time() > t) {
      if (corrected_) publish(sink, t);
      corrected_ = false;
      advance_predictions(clock, sink, t, true);
    }
  }

  static constexpr bool uses(const WheelTicksInput&) { return true; }
  static constexpr bool uses(const SteeringInput&) { return true; }
  static constexpr bool uses(const ScanInput&) { return Estimator::kUsesScans; }
  static constexpr bool uses(const LandmarkInput&) { return Estimator::kUsesLandmarks; }

  template <typename Clock, typename Measurement>
  void correct_at(Clock& clock, TimeNs t, const Measurement& z) {
    take_motion_until(t);
    if (t > last_predict_t_) predict_to(clock, t);
    const TimeNs t0 = clock();
    const StepOutcome o = est_.correct(z);
    account(o, clock() - t0);
    if (o != StepOutcome::rejected) ++counters_.corrections;
    corrected_ = true;
  }

  // Fixed-rate predictions up to t (inclusive or not), each followed by an output; a prediction time a scan already
  // predicted to is published without predicting again.
  template <typename Clock, typename Sink>
  void advance_predictions(Clock& clock, Sink& sink, TimeNs t, bool inclusive) {
    std::uint32_t catch_up = 0;
    while (inclusive ? next_predict_t_ <= t : next_predict_t_ < t) {
      if (++catch_up > timing_.max_catch_up_predictions) {  // a gap in the inputs: one prediction across it
        const TimeNs to = inclusive ? t : t - 1;
        if (to > last_predict_t_) predict_to(clock, to);
        publish(sink, to);
        next_predict_t_ = to + timing_.predict_period_ns;
        break;
      }
      if (next_predict_t_ > last_predict_t_) predict_to(clock, next_predict_t_);
      if (!published_any_ || next_predict_t_ != last_published_t_) publish(sink, next_predict_t_);
      next_predict_t_ += timing_.predict_period_ns;
    }
  }

  // Encoder increments cover (previous stamp, stamp]. When the next increment is already queued and spans the scan
  // time, the share up to the scan (linear in time, rounded toward zero) is moved into the pending motion; the rest
  // stays queued. Without it, the motion of a whole encoder period (or of a bus outage) would be applied after the
  // scan instead of before.
  void take_motion_until(TimeNs t) {
    QueuedInput* next = queue_.next_of_kind(InputKind::wheel_ticks);
    if (next == nullptr || !have_encoder_ || next->t_ns <= t || t <= ticks_until_t_) return;
    const float f = static_cast<float>(t - ticks_until_t_) / static_cast<float>(next->t_ns - ticks_until_t_);
    const std::int32_t l = static_cast<std::int32_t>(f * static_cast<float>(next->ticks.left_ticks));
    const std::int32_t r = static_cast<std::int32_t>(f * static_cast<float>(next->ticks.right_ticks));
    pending_left_ += l;
    pending_right_ += r;
    next->ticks.left_ticks -= l;
    next->ticks.right_ticks -= r;
    ticks_until_t_ = t;
  }

  template <typename Clock>
  void predict_to(Clock& clock, TimeNs t) {
    const MotionInput m{static_cast<float>(t - last_predict_t_) * 1.0e-9f, pending_left_, pending_right_, steering_rad_,
                        have_steering_};
    const TimeNs t0 = clock();
    const StepOutcome o = est_.predict(m);
    account(o, clock() - t0);
    if (o != StepOutcome::rejected) {
      ++counters_.predictions;
      pending_left_ = 0;
      pending_right_ = 0;
    }
    last_predict_t_ = t;
  }

  void account(StepOutcome o, TimeNs took) {
    if (o == StepOutcome::rejected) {
      ++counters_.rejected;
      sticky_ |= status::kInputRejected;
    } else if (o == StepOutcome::degenerate) {
      ++counters_.degenerate;
      sticky_ |= status::kFilterDegenerate;
    }
    if (took > counters_.worst_step_ns) counters_.worst_step_ns = took;
    if (took > timing_.step_deadline_ns) {
      ++counters_.overruns;
      sticky_ |= status::kDeadlineOverrun;
    }
  }

  template <typename Sink>
  void publish(Sink& sink, TimeNs t) {
    std::uint32_t s = sticky_;
    if (!have_encoder_ || t - last_encoder_t_ > timing_.encoder_timeout_ns) {
      s |= status::kEncoderTimeout;
      ++counters_.encoder_timeouts;
    }
    if (Estimator::kUsesSteering && (!have_steering_ || t - last_steering_t_ > timing_.steering_timeout_ns)) {
      s |= status::kSteeringTimeout;
      ++counters_.steering_timeouts;
    }
    if (Estimator::kUsesScans && (!have_scan_ || t - last_scan_t_ > timing_.scan_timeout_ns)) {
      s |= status::kScanTimeout;
      ++counters_.scan_timeouts;
    }
    if (Estimator::kUsesLandmarks && (!have_landmark_ || t - last_landmark_t_ > timing_.landmark_timeout_ns)) {
      s |= status::kLandmarkTimeout;
      ++counters_.landmark_timeouts;
    }
    sink(LoopOutput{t, est_.estimate(), s, &counters_});
    sticky_ = 0;
    published_any_ = true;
    last_published_t_ = t;
  }

  Estimator& est_;
  LoopTiming timing_;
  InputQueue<QueueCapacity, KMax, ScanSlots> queue_;
  LoopCounters counters_;
  std::uint32_t sticky_ = 0;
  bool seen_any_ = false, applied_any_ = false;
  bool have_encoder_ = false, have_steering_ = false, have_scan_ = false, have_landmark_ = false;
  bool corrected_ = false;  // a correction at the time being applied: publish once all its inputs are in
  TimeNs newest_t_ = 0, applied_t_ = 0, last_predict_t_ = 0, next_predict_t_ = 0;
  TimeNs last_encoder_t_ = 0, last_steering_t_ = 0, last_scan_t_ = 0, last_landmark_t_ = 0;
  TimeNs ticks_until_t_ = 0;
  TimeNs last_published_t_ = 0;
  bool published_any_ = false;  // the encoder motion up to this time is in pending_ or already predicted
  std::int32_t pending_left_ = 0, pending_right_ = 0;
  float steering_rad_ = 0.0f;
};

}  // namespace est::loop

#pragma once
// The fixed-rate filter loop: inputs are queued in timestamp order and applied once they are older than the reorder
// window behind the newest input, so the outputs depend only on the inputs and their timestamps, never on when they
// arrived or on the wall clock. Prediction runs at a fixed period of input time (e.g. 100 Hz) with the motion
// gathered since the last prediction (est/loop/motion_input.hpp); corrections (scans, landmark features) are applied
// at their own time after a prediction up to it; the output for a time is published once, after every input stamped
// with it. The clock is read only to time each step (deadline overruns are counted, results never depend on it).
//
// Every input kind is a row of est/loop/input_kinds.hpp: its role (increment, held, measurement), its status bit
// and its staleness limit (LoopTiming::staleness); the loop keeps one staleness clock and one pair of counters per
// kind.
//
// Estimator concept (est/loop/mcl_estimator.hpp, est/loop/ekf_estimator.hpp; est/loop/configured_loop.hpp picks one):
//   InputKinds inputs() const;                   the kinds it uses: its control assembler's and its measurements
//   StepOutcome predict(const MotionInput&);
//   StepOutcome correct(const ScanInput&);       if it corrects with scans
//   StepOutcome correct(const LandmarkInput&);   if it corrects with landmark features
//   StepOutcome end_of_frame();                  optional, with bool frame_pending() const: after the last
//                                                measurement of a stamp, before its output, when a frame is pending
//   PoseEstimate estimate() const;
// Inputs of a kind the estimator does not use (a lidar on the bus of an EKF on landmarks) are counted as unused and
// dropped when pushed: not a fault, no status bit.
//
// Storage, ETL style: FilterLoop<Estimator> works on an InputQueue of any capacity (est/loop/input_queue.hpp);
// FilterLoopStorage<Estimator, Capacity, KMax, ScanSlots> is the loop with its queue's arrays.
#include <cstdint>
#include <type_traits>
#include <utility>

#include "est/filter/particle_estimate.hpp"
#include "est/loop/input_kinds.hpp"
#include "est/loop/input_queue.hpp"
#include "est/loop/inputs.hpp"
#include "est/loop/loop_counters.hpp"
#include "est/loop/motion_input.hpp"
#include "est/loop/status.hpp"

namespace est::loop {

struct LoopTiming {
  TimeNs predict_period_ns = 10000000;     // 100 Hz
  TimeNs reorder_window_ns = 20000000;     // inputs up to 20 ms late are still applied in order
  StalenessLimits staleness{};             // per input kind (the table's defaults)
  TimeNs step_deadline_ns = 5000000;       // budget of one predict or correct step, as measured by the clock
  std::uint32_t max_catch_up_predictions = 100;  // after a longer gap in the inputs, the loop jumps (one prediction)
};

enum class StepOutcome : std::uint8_t { applied, rejected, degenerate };

struct LoopOutput {
  TimeNs t_ns;
  PoseEstimate estimate;
  std::uint32_t status;  // est::loop::status bits
  const LoopCounters* counters;
};

// Whether Estimator has correct(const Measurement&).
template <typename Estimator, typename Measurement, typename = void>
struct CorrectsWith : std::false_type {};
template <typename Estimator, typename Measurement>
struct CorrectsWith<Estimator, Measurement,
                    std::void_t<decltype(std::declval<Estimator&>().correct(std::declval<const Measurement&>()))>>
    : std::true_type {};

// Whether Estimator has end_of_frame() and frame_pending(): an estimator that gathers the measurements sharing a
// stamp (one sensor frame, e.g. for joint data association) fuses them there, before the output at that stamp. The
// loop calls (and times) it only when a frame is pending, so an estimator that gathers nothing steps as before.
template <typename Estimator, typename = void>
struct EndsFrames : std::false_type {};
template <typename Estimator>
struct EndsFrames<Estimator, std::void_t<decltype(std::declval<Estimator&>().end_of_frame()),
                                         decltype(std::declval<const Estimator&>().frame_pending())>>
    : std::true_type {};

template <typename Estimator>
class FilterLoop {
 public:
  FilterLoop(Estimator& estimator, InputQueue& queue, const LoopTiming& timing)
      : est_(estimator), queue_(queue), timing_(timing), uses_(usable(estimator.inputs())) {}
  FilterLoop(const FilterLoop&) = delete;
  FilterLoop& operator=(const FilterLoop&) = delete;

  // Queue an input. False (and counted) when its kind is not used, it is older than what was already applied, or
  // there is no room.
  template <typename Input>
  bool push(const Input& in) {
    constexpr InputKind kind = KindOf<Input>::value;
    if (!uses_.has(kind)) {
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
    ++counters_.of(kind).accepted;
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
  std::int32_t max_beams() const { return queue_.max_beams(); }
  InputKinds inputs() const { return uses_; }
  const Estimator& estimator() const { return est_; }

 private:
  // The kinds the estimator says it uses, less the measurements it has no correct() for.
  static InputKinds usable(InputKinds k) {
    if (!CorrectsWith<Estimator, ScanInput>::value) k = k.without(InputKind::scan);
    if (!CorrectsWith<Estimator, LandmarkInput>::value) k = k.without(InputKind::landmark);
    return k;
  }

  template <typename Clock, typename Sink>
  void apply_front(Clock& clock, Sink& sink) {
    const QueuedInput q = queue_.front();
    const TimeNs t = q.t_ns;
    if (!applied_any_) {
      applied_any_ = true;
      last_predict_t_ = t;
      next_predict_t_ = t + timing_.predict_period_ns;
      motion_.start(t);
    }
    // Predictions strictly before t: an increment stamped t is motion up to t, so it belongs in a prediction at t.
    advance_predictions(clock, sink, t, false);
    applied_t_ = t;
    switch (q.kind) {
      case InputKind::wheel_ticks: motion_.add(q.p.ticks); break;
      case InputKind::steering: motion_.add(q.p.steering); break;
      case InputKind::twist: motion_.add(q.p.twist); break;
      case InputKind::odometry: motion_.add(q.p.odometry); break;
      case InputKind::scan:
        if constexpr (CorrectsWith<Estimator, ScanInput>::value) correct_at(clock, t, queue_.scan(q));
        break;
      case InputKind::landmark:
        if constexpr (CorrectsWith<Estimator, LandmarkInput>::value) correct_at(clock, t, q.p.landmark);
        break;
    }
    last_t_[index_of(q.kind)] = t;
    have_[index_of(q.kind)] = true;
    queue_.pop();
    // The output at t and the prediction at t itself wait while more inputs stamped t are queued.
    if (queue_.empty() || queue_.front_time() > t) {
      if constexpr (EndsFrames<Estimator>::value) {
        if (corrected_ && est_.frame_pending()) {
          const TimeNs t0 = clock();
          account(est_.end_of_frame(), clock() - t0);
        }
      }
      if (corrected_) publish(sink, t);
      corrected_ = false;
      advance_predictions(clock, sink, t, true);
    }
  }

  template <typename Clock, typename Measurement>
  void correct_at(Clock& clock, TimeNs t, const Measurement& z) {
    motion_.take_ticks_share(queue_.next_of_kind(InputKind::wheel_ticks), t);
    motion_.take_odometry_share(queue_.next_of_kind(InputKind::odometry), t);
    if (t > last_predict_t_) predict_to(clock, t);
    const TimeNs t0 = clock();
    const StepOutcome o = est_.correct(z);
    account(o, clock() - t0);
    if (o != StepOutcome::rejected) ++counters_.corrections;
    corrected_ = true;
  }

  // Fixed-rate predictions up to t (inclusive or not), each followed by an output; a prediction time a correction
  // already predicted to is published without predicting again.
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

  template <typename Clock>
  void predict_to(Clock& clock, TimeNs t) {
    const MotionInput m = motion_.motion(last_predict_t_, t);
    const TimeNs t0 = clock();
    const StepOutcome o = est_.predict(m);
    account(o, clock() - t0);
    if (o != StepOutcome::rejected) {
      ++counters_.predictions;
      motion_.consumed();
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
    for (const InputKindInfo& k : kInputKinds) {
      const std::size_t i = index_of(k.kind);
      if (!uses_.has(k.kind)) continue;
      if (!have_[i] || t - last_t_[i] > timing_.staleness[k.kind]) {
        s |= k.stale_bit;
        ++counters_.kinds[i].stale;
      }
    }
    sink(LoopOutput{t, est_.estimate(), s, &counters_});
    sticky_ = 0;
    published_any_ = true;
    last_published_t_ = t;
  }

  Estimator& est_;
  InputQueue& queue_;
  LoopTiming timing_;
  InputKinds uses_;
  LoopCounters counters_;
  MotionGather motion_;
  std::uint32_t sticky_ = 0;
  bool seen_any_ = false, applied_any_ = false;
  bool corrected_ = false;  // a correction at the time being applied: publish once all its inputs are in
  bool have_[kInputKindCount] = {};
  TimeNs last_t_[kInputKindCount] = {};
  TimeNs newest_t_ = 0, applied_t_ = 0, last_predict_t_ = 0, next_predict_t_ = 0;
  TimeNs last_published_t_ = 0;
  bool published_any_ = false;
};

namespace detail {
template <std::uint32_t Capacity, std::int32_t KMax, std::uint32_t ScanSlots>
struct QueueMember {  // constructed before the loop that refers to it (base-from-member)
  InputQueueStorage<Capacity, KMax, ScanSlots> queue_storage;
};
}  // namespace detail

template <typename Estimator, std::uint32_t Capacity, std::int32_t KMax, std::uint32_t ScanSlots = 2>
class FilterLoopStorage final : private detail::QueueMember<Capacity, KMax, ScanSlots>, public FilterLoop<Estimator> {
 public:
  FilterLoopStorage(Estimator& estimator, const LoopTiming& timing)
      : detail::QueueMember<Capacity, KMax, ScanSlots>{}, FilterLoop<Estimator>(estimator, this->queue_storage, timing) {}
};

}  // namespace est::loop

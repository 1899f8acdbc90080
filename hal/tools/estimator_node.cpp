// estimator_node: the firmware's filter loop on the host. Live, it reads sensor inputs from SocketCAN (--can) and/or
// LCM (--lcm) and publishes estimates on LCM (and CAN with --can-out); with --replay it runs an LCM log through the
// same loop in lockstep, as fast as it can, and writes the estimates to an LCM log, deterministically.
//
// Data path: transport -> hal::ValidatedInputs (checks, counted rejects) -> [InputRecorder] -> hal::LoopPort ->
// est::loop::FilterLoop<MclEstimator> -> hal::EstimateSink (LCM, CAN, log file).
// Time: live, CAN inputs carry the kernel's receive time and LCM inputs their sender's stamp_ns, checked against
// CLOCK_MONOTONIC; in replay the HAL's clock reads each message's own stamp_ns (so staleness, a property of live
// arrival that a log does not keep, never fires) and the loop's step clock stands still (no overruns, no timing
// in the outputs): the output log is a function of the input log and the options alone.
#include <poll.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>

#include "hal/can/can_estimate_sink.hpp"
#include "hal/can/can_input.hpp"
#include "hal/can/estimator_dbc.hpp"
#include "hal/can/scan_reassembler.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/socketcan/socketcan_bus.hpp"
#include "hal/status_word.hpp"
#include "hal/validated_inputs.hpp"
#include "lcm_log_io.hpp"
#include "node_config.hpp"
#include "pipeline.hpp"

namespace {

using hal::TimeNs;
using namespace hal::node;

std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig); }

struct MonotonicClock final : hal::Clock {
  TimeNs now_ns() override { return hal::socketcan::monotonic_now_ns(); }
};
// Replay: the HAL's checks see each sample at its own stamp.
struct StampClock final : hal::Clock {
  TimeNs now = 0;
  TimeNs now_ns() override { return now; }
};
// Replay: steps take no time (timing is not part of a lockstep replay's results).
struct FrozenClock final : hal::Clock {
  TimeNs now_ns() override { return 0; }
};

class StampedPort final : public hal::SensorPort {
 public:
  StampedPort(StampClock& clock, hal::SensorPort& next) : clock_(clock), next_(next) {}
  void on_wheel_ticks(const hal::WheelTicks& s) override {
    clock_.now = s.stamp_ns;
    next_.on_wheel_ticks(s);
  }
  void on_steering(const hal::SteeringSample& s) override {
    clock_.now = s.stamp_ns;
    next_.on_steering(s);
  }
  void on_range_scan(const hal::RangeScanView& s) override {
    clock_.now = s.stamp_ns;
    next_.on_range_scan(s);
  }
  void on_landmarks(const hal::LandmarkSightingView& s) override {
    clock_.now = s.stamp_ns;
    next_.on_landmarks(s);
  }

 private:
  StampClock& clock_;
  hal::SensorPort& next_;
};

// Counts what reaches the loop, by kind (after validation).
class CountingPort final : public hal::ValidatedSensorPort {
 public:
  explicit CountingPort(hal::ValidatedSensorPort& next) : next_(next) {}
  void on_wheel_motion(const hal::WheelTickDelta& d) override {
    ++wheel_ticks;
    next_.on_wheel_motion(d);
  }
  void on_steering(const hal::SteeringSample& s) override {
    ++steering;
    next_.on_steering(s);
  }
  void on_range_scan(const hal::RangeScanView& s) override {
    ++scans;
    next_.on_range_scan(s);
  }
  void on_landmarks(const hal::LandmarkSightingView& s) override {
    ++sightings;
    next_.on_landmarks(s);
  }
  std::uint64_t wheel_ticks = 0, steering = 0, scans = 0, sightings = 0;

 private:
  hal::ValidatedSensorPort& next_;
};

// Every estimate to every output; status_t at a fixed rate of input time.
class NodeOutputs final : public hal::EstimateSink {
 public:
  NodeOutputs(const NodeConfig& c, std::function<est_lcm::status_t(const hal::Estimate&)> make_status)
      : channels_(c.channels),
        status_period_ns_(c.status_hz > 0.0 ? static_cast<TimeNs>(1.0e9 / c.status_hz) : 0),
        make_status_(std::move(make_status)) {}

  hal::lcm::LcmOutputs* lcm = nullptr;
  hal::can::CanEstimateSink* can = nullptr;
  LogWriter* log = nullptr;

  void publish(const hal::Estimate& e) override {
    ++count_;
    last_ = e;
    if (lcm != nullptr) lcm->publish(e);
    if (can != nullptr) can->publish(e);
    if (log != nullptr) log->write(channels_.pose, e.stamp_ns, hal::lcm::to_lcm(e));
    if (status_period_ns_ > 0 && (!status_started_ || e.stamp_ns >= next_status_ns_)) {
      publish_status(e);
      status_started_ = true;
      next_status_ns_ = (e.stamp_ns / status_period_ns_ + 1) * status_period_ns_;
    }
  }
  void publish_status(const hal::Estimate& e) {
    const est_lcm::status_t s = make_status_(e);
    if (lcm != nullptr) lcm->publish_status(s);
    if (log != nullptr) log->write(channels_.status, e.stamp_ns, s);
  }
  void final_status() {
    if (count_ > 0) publish_status(last_);
  }
  std::uint64_t count() const { return count_; }

 private:
  hal::lcm::Channels channels_;
  TimeNs status_period_ns_;
  std::function<est_lcm::status_t(const hal::Estimate&)> make_status_;
  bool status_started_ = false;
  TimeNs next_status_ns_ = 0;
  std::uint64_t count_ = 0;
  hal::Estimate last_;
};

template <typename Reason, typename Counters>
std::string reason_list(const Counters& c) {
  std::string s;
  for (std::size_t i = 1; i < static_cast<std::size_t>(Reason::kCount); ++i) {
    const auto r = static_cast<Reason>(i);
    s += " ";
    s += to_string(r);
    s += "=" + std::to_string(c[r]);
  }
  return s;
}

std::uint32_t saturate(std::uint64_t v) { return v > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(v); }

class Node {
 public:
  explicit Node(const NodeConfig& c) : c_(c) {}

  int run() {
    const bool replay = !c_.replay_path.empty();
    hal::InputLimits limits = c_.limits;
    limits.wheels.counter_bits = static_cast<std::uint8_t>(
        !c_.can_interface.empty() ? hal::can::kCanWheelCounterBits : c_.lcm_wheel_counter_bits);
    if (!c_.can_interface.empty() && c_.lcm_input && c_.lcm_wheel_counter_bits != hal::can::kCanWheelCounterBits)
      std::fprintf(stderr, "estimator_node: with --can, LCM encoder messages must carry 16-bit counters too\n");

    NodeOutputs outputs(c_, [this](const hal::Estimate& e) { return status_message(e); });
    hal::Clock& step_clock = replay ? static_cast<hal::Clock&>(frozen_) : static_cast<hal::Clock&>(monotonic_);
    pipeline_ = make_pipeline(c_, step_clock, outputs);

    std::unique_ptr<LogWriter> out_log, record_log;
    if (!c_.out_path.empty()) {
      out_log = std::make_unique<LogWriter>(c_.out_path);
      outputs.log = out_log.get();
    }
    counting_ = std::make_unique<CountingPort>(pipeline_->port());
    hal::ValidatedSensorPort* to_loop = counting_.get();
    std::unique_ptr<InputRecorder> recorder;
    if (!c_.record_path.empty()) {
      record_log = std::make_unique<LogWriter>(c_.record_path);
      recorder = std::make_unique<InputRecorder>(*record_log, c_.channels, *to_loop);
      to_loop = recorder.get();
    }
    hal::Clock& hal_clock = replay ? static_cast<hal::Clock&>(stamp_clock_) : static_cast<hal::Clock&>(monotonic_);
    validated_ = std::make_unique<hal::ValidatedInputs>(limits, hal_clock, *to_loop);

    const auto wall_start = std::chrono::steady_clock::now();
    const int rc = replay ? run_replay() : run_live(outputs);
    pipeline_->flush();
    outputs.final_status();
    wall_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (!c_.quiet) print_summary(replay, outputs, out_log.get(), record_log.get());
    return rc;
  }

 private:
  hal::lcm::InputConfig lcm_input_config(unsigned counter_bits) const {
    hal::lcm::InputConfig ic;
    ic.channels = c_.channels;
    ic.wheel_counter_bits = counter_bits;
    ic.max_ranges = static_cast<std::size_t>(kMaxBeams);
    return ic;
  }

  // Rejected upstream of the loop: HAL validation, CAN frames and scans, LCM decoding.
  std::uint32_t upstream_rejects() const {
    std::uint64_t n = validated_->faults().total();
    if (can_input_) n += can_input_->rejects().total() + can_input_->scans().rejects().total();
    if (lcm_inputs_) n += lcm_inputs_->rejects().total();
    return saturate(n);
  }

  void refresh(std::uint32_t transport_bits) {
    if (lcm_inputs_ && lcm_inputs_->rejects().total() != lcm_rejects_seen_) {
      lcm_rejects_seen_ = lcm_inputs_->rejects().total();
      transport_bits |= hal::status::kLcmDecodeError;
    }
    pipeline_->set_transport_status(transport_bits);
    pipeline_->set_upstream_rejects(upstream_rejects());
  }

  est_lcm::status_t status_message(const hal::Estimate& e) const {
    est_lcm::status_t s{};
    s.stamp_ns = e.stamp_ns;
    s.status_word = static_cast<std::int32_t>(e.status);
    const est::loop::LoopCounters& lc = pipeline_->loop_counters();
    s.steps = std::int64_t{lc.predictions} + lc.corrections;
    s.deadline_overruns = lc.overruns;
    const hal::FaultCounters f = validated_->faults();
    for (std::size_t i = 0; i < hal::kFaultCount; ++i) s.input_faults.push_back(f.count[i]);
    if (can_input_) {
      for (std::uint32_t v : can_input_->rejects().count) s.can_frame_rejects.push_back(v);
      for (std::uint32_t v : can_input_->scans().rejects().count) s.can_scan_rejects.push_back(v);
    }
    s.num_input_faults = static_cast<std::int16_t>(s.input_faults.size());
    s.num_can_frame_rejects = static_cast<std::int16_t>(s.can_frame_rejects.size());
    s.num_can_scan_rejects = static_cast<std::int16_t>(s.can_scan_rejects.size());
    return s;
  }

  int run_replay() {
    ::lcm::LogFile in(c_.replay_path, "r");
    if (!in.good()) {
      std::fprintf(stderr, "estimator_node: cannot read %s\n", c_.replay_path.c_str());
      return 1;
    }
    // memq: the backend's own decoding and checks, driven one message at a time.
    lcm_in_ = std::make_unique<::lcm::LCM>("memq://");
    ::lcm::LCM& bus = *lcm_in_;
    stamped_ = std::make_unique<StampedPort>(stamp_clock_, *validated_);
    lcm_inputs_ = std::make_unique<hal::lcm::LcmInputs>(bus, lcm_input_config(c_.lcm_wheel_counter_bits), *stamped_);
    const hal::lcm::Channels& ch = c_.channels;
    refresh(0);
    while (g_stop_signal.load() == 0) {
      const ::lcm::LogEvent* ev = in.readNextEvent();
      if (ev == nullptr) break;
      ++log_events_;
      if (ev->channel != ch.wheel_ticks && ev->channel != ch.steering && ev->channel != ch.range_scan &&
          ev->channel != ch.landmarks)
        continue;
      ++log_inputs_;
      bus.publish(ev->channel, ev->data, static_cast<unsigned>(ev->datalen));
      bus.handle();
      refresh(0);
    }
    return 0;
  }

  int run_live(NodeOutputs& outputs) {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);

    std::unique_ptr<::lcm::LCM>& lcm_in = lcm_in_;
    std::unique_ptr<::lcm::LCM>& lcm_out = lcm_out_;
    if (c_.lcm_input) {
      lcm_in = std::make_unique<::lcm::LCM>(c_.lcm_url);
      if (!lcm_in->good()) {
        std::fprintf(stderr, "estimator_node: cannot open LCM %s\n", c_.lcm_url.c_str());
        return 1;
      }
      lcm_inputs_ = std::make_unique<hal::lcm::LcmInputs>(
          *lcm_in, lcm_input_config(c_.can_interface.empty() ? c_.lcm_wheel_counter_bits : hal::can::kCanWheelCounterBits),
          *validated_);
    }
    ::lcm::LCM* out = lcm_in.get();
    if (out == nullptr || c_.lcm_out_url != c_.lcm_url) {
      lcm_out = std::make_unique<::lcm::LCM>(c_.lcm_out_url);
      if (!lcm_out->good()) {
        std::fprintf(stderr, "estimator_node: cannot open LCM %s for the outputs\n", c_.lcm_out_url.c_str());
        return 1;
      }
      out = lcm_out.get();
    }
    lcm_outputs_ = std::make_unique<hal::lcm::LcmOutputs>(*out, c_.channels);
    outputs.lcm = lcm_outputs_.get();

    if (!c_.can_interface.empty()) {
      hal::socketcan::Config bc;
      bc.interface = c_.can_interface;
      bc.receive_ids.assign(std::begin(hal::can::dbc::kInputIds), std::end(hal::can::dbc::kInputIds));
      bus_ = std::make_unique<hal::socketcan::SocketCanBus>(bc);
      if (!bus_->open())
        std::fprintf(stderr, "estimator_node: %s: %s (retrying)\n", c_.can_interface.c_str(), bus_->last_error().c_str());
      scans_ = std::make_unique<hal::can::ScanReassembler<static_cast<std::size_t>(kMaxBeams)>>();
      can_input_ = std::make_unique<hal::can::CanInput>(*scans_, *validated_);
      if (c_.can_out) {
        can_sink_ = std::make_unique<hal::can::CanEstimateSink>(*bus_);
        outputs.can = can_sink_.get();
      }
    }

    std::fprintf(stderr, "estimator_node: running (%s%s%s%s)\n", c_.can_interface.empty() ? "" : "can ",
                 c_.can_interface.c_str(), c_.lcm_input ? " lcm " : "", c_.lcm_input ? c_.lcm_url.c_str() : "");
    const TimeNs end_ns = c_.duration_s > 0.0 ? monotonic_.now_ns() + static_cast<TimeNs>(c_.duration_s * 1.0e9) : 0;
    hal::socketcan::RxFrame frames[64];
    while (g_stop_signal.load() == 0) {
      pollfd fds[2];
      nfds_t n = 0;
      if (bus_ && bus_->is_open()) fds[n++] = {bus_->fd(), POLLIN, 0};
      if (lcm_in) fds[n++] = {lcm_in->getFileno(), POLLIN, 0};
      ::poll(fds, n, 10);
      const TimeNs now = monotonic_.now_ns();
      if (end_ns != 0 && now >= end_ns) break;
      if (bus_) {
        bus_->service(now);
        // Bounded: at most 16 reads of 64 frames per wake-up, so LCM and the stop signal are never starved.
        for (int batch = 0; batch < 16; ++batch) {
          const std::size_t got = bus_->receive(frames, 64);
          for (std::size_t i = 0; i < got; ++i) {
            refresh(bus_->take_status());
            can_input_->on_frame(frames[i].frame, frames[i].stamp_ns);
          }
          if (got < 64) break;
        }
        can_input_->poll(now);
      }
      if (lcm_in) {
        refresh(bus_ ? bus_->take_status() : 0u);
        for (int k = 0; k < 256 && lcm_in->handleTimeout(0) > 0; ++k) refresh(bus_ ? bus_->take_status() : 0u);
      }
    }
    stop_signal_ = g_stop_signal.load();
    return 0;
  }

  void print_summary(bool replay, const NodeOutputs& outputs, const LogWriter* out_log, const LogWriter* record_log) {
    const est::loop::LoopCounters& lc = pipeline_->loop_counters();
    std::FILE* f = stderr;
    std::fprintf(f, "estimator_node summary (%s%s)\n", replay ? "replay" : "live",
                 stop_signal_ == SIGINT ? ", stopped by SIGINT" : stop_signal_ == SIGTERM ? ", stopped by SIGTERM" : "");
    std::fprintf(f, "  map: %s; filter: %s\n", pipeline_->map_description().c_str(),
                 pipeline_->filter_description().c_str());
    if (replay)
      std::fprintf(f, "  log: events=%llu inputs=%llu wall_s=%.3f\n", static_cast<unsigned long long>(log_events_),
                   static_cast<unsigned long long>(log_inputs_), wall_s_);
    else
      std::fprintf(f, "  run: wall_s=%.3f\n", wall_s_);
    std::fprintf(f, "  inputs: wheel_ticks=%llu steering=%llu scans=%llu landmark_sightings=%llu (validated, handed to the loop)\n",
                 static_cast<unsigned long long>(counting_->wheel_ticks),
                 static_cast<unsigned long long>(counting_->steering), static_cast<unsigned long long>(counting_->scans),
                 static_cast<unsigned long long>(counting_->sightings));
    std::fprintf(f,
                 "  loop: inputs=%u too_old=%u queue_full=%u rejected=%u predictions=%u corrections=%u degenerate=%u "
                 "overruns=%u worst_step_us=%.1f encoder_timeouts=%u steering_timeouts=%u scan_timeouts=%u "
                 "landmark_timeouts=%u unused=%u\n",
                 lc.inputs, lc.too_old, lc.queue_full, lc.rejected, lc.predictions, lc.corrections, lc.degenerate,
                 lc.overruns, static_cast<double>(lc.worst_step_ns) / 1000.0, lc.encoder_timeouts, lc.steering_timeouts,
                 lc.scan_timeouts, lc.landmark_timeouts, lc.unused);
    std::fprintf(f, "  estimates: published=%llu nonfinite_held=%u\n", static_cast<unsigned long long>(outputs.count()),
                 pipeline_->nonfinite_estimates());
    std::fprintf(f, "  rejects: total=%u\n", upstream_rejects() + pipeline_->port_rejects().total());
    std::fprintf(f, "  rejects.wheel_ticks:%s\n", reason_list<hal::Fault>(validated_->wheels().faults()).c_str());
    std::fprintf(f, "  rejects.steering:%s\n", reason_list<hal::Fault>(validated_->steering().faults()).c_str());
    std::fprintf(f, "  rejects.scan:%s\n", reason_list<hal::Fault>(validated_->scan().faults()).c_str());
    std::fprintf(f, "  rejects.landmarks:%s\n", reason_list<hal::Fault>(validated_->landmarks().faults()).c_str());
    std::fprintf(f, "  rejects.loop_port:%s\n", reason_list<hal::LoopPortReject>(pipeline_->port_rejects()).c_str());
    if (lcm_inputs_)
      std::fprintf(f, "  rejects.lcm:%s accepted=%llu\n", reason_list<hal::lcm::LcmReject>(lcm_inputs_->rejects()).c_str(),
                   static_cast<unsigned long long>(lcm_inputs_->accepted()));
    if (can_input_) {
      std::fprintf(f, "  rejects.can_frame:%s accepted=%u\n",
                   reason_list<hal::can::FrameReject>(can_input_->rejects()).c_str(), can_input_->frames_accepted());
      std::fprintf(f, "  rejects.can_scan:%s completed=%u\n",
                   reason_list<hal::can::ScanReject>(can_input_->scans().rejects()).c_str(),
                   can_input_->scans().scans_completed());
    }
    if (bus_) {
      const hal::socketcan::Counters& b = bus_->counters();
      std::fprintf(f,
                   "  can: rx_frames=%llu tx_frames=%llu tx_failed=%llu rx_dropped=%llu error_frames=%llu "
                   "bus_off=%llu link_lost=%llu reconnects=%llu\n",
                   static_cast<unsigned long long>(b.rx_frames), static_cast<unsigned long long>(b.tx_frames),
                   static_cast<unsigned long long>(b.tx_failed), static_cast<unsigned long long>(b.rx_dropped),
                   static_cast<unsigned long long>(b.error_frames), static_cast<unsigned long long>(b.bus_off_events),
                   static_cast<unsigned long long>(b.link_lost), static_cast<unsigned long long>(b.reconnects));
    }
    if (lcm_outputs_)
      std::fprintf(f, "  lcm_out: publish_failures=%llu\n",
                   static_cast<unsigned long long>(lcm_outputs_->publish_failures()));
    if (out_log != nullptr)
      std::fprintf(f, "  out_log: events=%llu failures=%llu\n", static_cast<unsigned long long>(out_log->events()),
                   static_cast<unsigned long long>(out_log->failures()));
    if (record_log != nullptr)
      std::fprintf(f, "  record_log: events=%llu failures=%llu\n", static_cast<unsigned long long>(record_log->events()),
                   static_cast<unsigned long long>(record_log->failures()));
  }

  const NodeConfig& c_;
  MonotonicClock monotonic_;
  StampClock stamp_clock_;
  FrozenClock frozen_;
  std::unique_ptr<Pipeline> pipeline_;
  std::unique_ptr<CountingPort> counting_;
  std::unique_ptr<hal::ValidatedInputs> validated_;
  std::unique_ptr<StampedPort> stamped_;
  // The LCM instances outlive the backend objects that subscribe on them (members are destroyed in reverse).
  std::unique_ptr<::lcm::LCM> lcm_in_, lcm_out_;
  std::unique_ptr<hal::lcm::LcmInputs> lcm_inputs_;
  std::unique_ptr<hal::lcm::LcmOutputs> lcm_outputs_;
  std::unique_ptr<hal::socketcan::SocketCanBus> bus_;
  std::unique_ptr<hal::can::ScanReassembler<static_cast<std::size_t>(kMaxBeams)>> scans_;
  std::unique_ptr<hal::can::CanInput> can_input_;
  std::unique_ptr<hal::can::CanEstimateSink> can_sink_;
  std::uint32_t lcm_rejects_seen_ = 0;
  std::uint64_t log_events_ = 0, log_inputs_ = 0;
  double wall_s_ = 0.0;
  int stop_signal_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "estimator_node: the firmware's filter loop (augmented MCL on a map) on the host.\n"
      "Live: sensor inputs from SocketCAN (--can) and/or LCM (--lcm), estimates out on LCM (pose_estimate_t, "
      "status_t) and CAN (--can-out); stops on SIGINT/SIGTERM (or --duration) with a summary of counts on stderr.\n"
      "Replay: --replay IN.lcmlog --out OUT.lcmlog runs a log through the loop in lockstep, as fast as possible; "
      "the same log and options give the same OUT, bit for bit."};
  NodeConfig config;
  add_options(app, config);
  try {
    app.parse(argc, argv);
    finish_options(app, config);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    Node node(config);
    return node.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "estimator_node: %s\n", e.what());
    return 1;
  }
}

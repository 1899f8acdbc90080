// estimator_node as a library (node/node.hpp).
#include "node/node.hpp"

#include <poll.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/slam_map_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "est/map/distance_transform.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "hal/can/can_estimate_sink.hpp"
#include "hal/can/can_input.hpp"
#include "hal/can/candump.hpp"
#include "hal/can/estimator_dbc.hpp"
#include "hal/forward.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "hal/maps/landmark_file.hpp"
#include "hal/maps/ros_map_loader.hpp"
#include "hal/socketcan/socketcan_bus.hpp"
#include "hal/status_word.hpp"
#include "node/lcm_log_io.hpp"
#include "node/lcm_receiver.hpp"
#include "node/stamp_alignment.hpp"
#include "node/pacer.hpp"
#include "node/udp_drops.hpp"
#include "node/view_feed.hpp"
#include "view/live_view.hpp"
#include "world/office_map.hpp"

namespace node {

namespace {

std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) { g_stop_signal.store(sig); }

// The node's clock: the monotonic clock, or with --live-speed S a clock that runs S times faster from start-up (the
// time of a stream played at S times real time).
struct MonotonicClock final : hal::Clock {
  explicit MonotonicClock(double speed = 1.0) : speed_(speed), origin_ns_(hal::socketcan::monotonic_now_ns()) {}
  TimeNs now_ns() override { return at(hal::socketcan::monotonic_now_ns()); }
  // A time of the monotonic clock on this one.
  TimeNs at(TimeNs monotonic_ns) const {
    if (speed_ == 1.0) return monotonic_ns;
    return origin_ns_ + static_cast<TimeNs>(static_cast<double>(monotonic_ns - origin_ns_) * speed_);
  }

 private:
  double speed_;
  TimeNs origin_ns_;
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

std::uint32_t saturate(std::uint64_t v) { return v > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(v); }

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

// The maps of a run, loaded once and outliving the pipeline.
struct LoadedMaps {
  est::OccupancyGridStorage<kMapMaxSide, kMapMaxSide> grid;
  est::DistanceTransformStorage<kMapMaxSide, kMapMaxSide> edt;
  est::LandmarkMapStorage<kMaxLandmarks> landmarks;
  EstimatorMaps view;
};

std::unique_ptr<LoadedMaps> load_maps(const NodeConfig& c) {
  auto m = std::make_unique<LoadedMaps>();
  if (c.spec.filter == est::loop::Filter::ekf_slam) {
    m->view.description = "none (EKF-SLAM maps the landmarks it sees)";
    return m;
  }
  if (c.spec.filter == est::loop::Filter::ekf || c.spec.mcl_landmarks) {
    if (c.landmarks == "office") {
      est::sim::make_office_landmarks(m->landmarks);
      m->view.description = "office landmarks (the simulator's, 16 posts)";
    } else {
      hal::maps::load_landmark_csv(c.landmarks, m->landmarks);
      m->view.description = c.landmarks + " (" + std::to_string(m->landmarks.size()) + " landmarks)";
    }
    if (m->landmarks.size() == 0)  // a landmark filter without landmarks would run on odometry alone, silently
      throw std::runtime_error(std::string(c.spec.filter == est::loop::Filter::ekf ? "--filter ekf" : "--mcl-landmarks") +
                               " needs landmarks, and " + c.landmarks + " has none");
    m->view.landmarks = m->landmarks.view();
    if (c.spec.filter == est::loop::Filter::ekf) return m;
  }
  if (c.map == "office") {
    est::sim::make_office_map(m->grid);
    m->view.description = "office (the simulator's, 20 m x 15 m at 0.05 m)";
  } else {
    const hal::maps::RosMapInfo info = hal::maps::load_ros_map(c.map, m->grid);
    m->view.description = c.map + " (" + std::to_string(m->grid.width()) + " x " + std::to_string(m->grid.height()) +
                          " at " + std::to_string(info.resolution) + " m)";
  }
  if (m->edt.build(m->grid.grid()) != est::MapStatus::ok) throw std::runtime_error("map: distance transform failed");
  m->view.grid = m->grid.grid();
  m->view.edt = m->edt.view();
  return m;
}

// EKF-SLAM's map and association counters as they are now.
est_lcm::slam_map_t slam_map_message(const EstimatorPipeline& p, TimeNs stamp_ns) {
  const est::loop::SlamAssociationCounters& c = *p.slam_counters();
  est_lcm::slam_map_t m{};
  m.stamp_ns = stamp_ns;
  m.tentative_landmarks = p.slam_tentative_landmarks();
  m.frames = c.frames;
  m.associated = c.associated;
  m.created = c.created;
  m.discarded = c.discarded;
  m.beyond_range = c.beyond_range;
  m.held_tentative = c.tentative;
  m.update_refused = c.update_refused;
  m.insert_refused = c.insert_refused;
  m.map_full = c.map_full;
  m.tentative_full = c.tentative_full;
  m.bad_input = c.bad_input;
  m.tentative_forgotten = c.tentative_forgotten;
  m.num_landmarks = p.slam_landmarks();
  for (int k = 0; k < m.num_landmarks; ++k) {
    const est::Landmark l = p.slam_landmark(k);
    m.x_m.push_back(l.x);
    m.y_m.push_back(l.y);
    m.signature.push_back(l.signature);
  }
  return m;
}

// Every estimate to every output; status_t at a fixed rate of input time (with EKF-SLAM's map).
class NodeOutputs final : public hal::EstimateSink {
 public:
  NodeOutputs(const NodeConfig& c, std::function<est_lcm::status_t(const hal::Estimate&)> make_status)
      : channels_(c.channels),
        status_period_ns_(c.status_hz > 0.0 ? static_cast<TimeNs>(1.0e9 / c.status_hz) : 0),
        make_status_(std::move(make_status)) {}

  hal::lcm::LcmOutputs* lcm = nullptr;
  hal::can::CanEstimateSink* can = nullptr;
  LogWriter* log = nullptr;
  const EstimatorPipeline* slam = nullptr;  // EKF-SLAM: its map and counters go out with each status
  CandumpWriter* candump = nullptr;
  hal::can::CanEstimateSink* candump_sink = nullptr;
  const StampAlignment* sender_time = nullptr;  // live, aligned: estimates out in the sender's time
  view::LiveView* view = nullptr;

  void publish(const hal::Estimate& loop_estimate) override {
    hal::Estimate e = loop_estimate;
    if (sender_time != nullptr) e.stamp_ns = sender_time->to_sender(e.stamp_ns);
    ++count_;
    last_ = e;
    if (view != nullptr) view->publish_estimate(view_sample(e));
    if (lcm != nullptr) lcm->publish(e);
    if (can != nullptr) can->publish(e);
    if (candump_sink != nullptr) {
      candump->set_stamp(e.stamp_ns);
      candump_sink->publish(e);
    }
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
    if (slam != nullptr && slam->slam_counters() != nullptr) {
      const est_lcm::slam_map_t m = slam_map_message(*slam, e.stamp_ns);
      if (lcm != nullptr) lcm->publish_slam_map(m);
      if (log != nullptr) log->write(channels_.slam_map, e.stamp_ns, m);
    }
  }
  void final_status() {
    if (count_ > 0) publish_status(last_);
  }
  std::uint64_t count() const { return count_; }
  TimeNs last_stamp() const { return last_.stamp_ns; }

 private:
  hal::lcm::Channels channels_;
  TimeNs status_period_ns_;
  std::function<est_lcm::status_t(const hal::Estimate&)> make_status_;
  bool status_started_ = false;
  TimeNs next_status_ns_ = 0;
  std::uint64_t count_ = 0;
  hal::Estimate last_;
};

// Counts the checked inputs that reach the loop, by kind.
struct CountHook {
  std::uint64_t* counts;
  template <typename Checked>
  void operator()(const Checked&) {
    ++counts[est::loop::index_of(hal::KindOfChecked<Checked>::value)];
  }
};
// Records the inputs in the sender's time when a live node aligns them (as its estimates are).
struct SenderTimeRecorder {
  InputRecorder record;
  const StampAlignment* const* sender_time;
  template <typename Checked>
  void operator()(const Checked& s) {
    if (*sender_time != nullptr)
      record(shifted(s, -(*sender_time)->offset_ns()));
    else
      record(s);
  }
};
// Stamps the replay's HAL clock with each raw sample's own stamp.
struct StampHook {
  StampClock* clock;
  template <typename Raw>
  void operator()(const Raw& s) {
    clock->now = s.stamp_ns;
  }
};

// What the filter starts from, as the node says it at start-up (a node restarted mid-run starts from here again).
std::string initial_belief(const EstimatorSpec& s) {
  char text[200];
  if (s.global)
    std::snprintf(text, sizeof text, "global localization, %u particles uniform over the free space",
                  static_cast<unsigned>(s.particles));
  else
    std::snprintf(text, sizeof text, "tracking from x=%.3f m y=%.3f m theta=%.3f rad (sigma %.3f m, %.3f rad)",
                  static_cast<double>(s.initial_pose.x), static_cast<double>(s.initial_pose.y),
                  static_cast<double>(s.initial_pose.theta), static_cast<double>(s.initial_sigma_xy_m),
                  static_cast<double>(s.initial_sigma_theta_rad));
  return text;
}

}  // namespace

struct Node::Impl {
  explicit Impl(const NodeConfig& config)
      : c(config),
        replay(config.replay()),
        monotonic(config.live_speed),
        maps(load_maps(config)),
        outputs(config, [this](const hal::Estimate& e) { return status_message(e); }) {
    hal::Clock& step_clock = replay ? static_cast<hal::Clock&>(frozen) : static_cast<hal::Clock&>(monotonic);
    hal::Clock& sample_clock = replay ? static_cast<hal::Clock&>(stamp_clock) : static_cast<hal::Clock&>(monotonic);
    EstimatorSpec spec = c.spec;
    spec.limits.wheels.counter_bits = static_cast<std::uint8_t>(
        !c.can_interface.empty() || !c.replay_can_path.empty() ? hal::can::kCanWheelCounterBits
                                                               : c.lcm_wheel_counter_bits);
    pipeline = make_estimator_pipeline(spec, maps->view, sample_clock, step_clock, outputs);
    outputs.slam = pipeline.get();
    if (!replay && c.lcm_input && c.align_stamps) {
      alignment = std::make_unique<StampAlignment>(monotonic, spec.limits.wheels.timing, c.channels, pipeline->input());
      // With CAN inputs besides, the node's clock is theirs (the kernel's receive time): the outputs stay on it.
      if (c.can_interface.empty()) outputs.sender_time = alignment.get();
    }
    counter = std::make_unique<hal::Forward<hal::ValidatedSensorPort, CountHook>>(pipeline->adapter(),
                                                                                CountHook{to_loop});
    if (!c.record_path.empty()) {
      record_log = std::make_unique<LogWriter>(c.record_path);
      recorder = std::make_unique<hal::Forward<hal::ValidatedSensorPort, SenderTimeRecorder>>(
          pipeline->adapter(), SenderTimeRecorder{InputRecorder(*record_log, c.channels), &outputs.sender_time});
      counter->set_next(*recorder);
    }
    pipeline->set_tap(*counter);
    if (!c.out_path.empty()) {
      out_log = std::make_unique<LogWriter>(c.out_path);
      outputs.log = out_log.get();
    }
    if (c.view_port != 0) start_view();
    if (!c.out_can_path.empty()) {
      candump = std::make_unique<CandumpWriter>(c.out_can_path, "can0");
      candump_sink = std::make_unique<hal::can::CanEstimateSink>(*candump);
      outputs.candump = candump.get();
      outputs.candump_sink = candump_sink.get();
    }
  }

  void start_view() {
    view = open_view(c.view_port, "estimator_node");
    if (maps->view.grid.valid()) view->set_map(view_map(maps->view.grid));
    outputs.view = view.get();
  }

  // MCL's particles to the view, at its rate.
  void feed_view() {
    if (view) feed_particles(*view, *pipeline, outputs.last_stamp());
  }
  // The ground truth, when the input carries it (a sim_host record log, or its LCM channel live).
  void view_truth(const void* data, std::size_t size) {
    est_lcm::ground_truth_t g;
    if (g.decode(data, 0, static_cast<int>(size)) < 0) return;
    view->publish_truth(g.stamp_ns,
                        {static_cast<double>(g.x_m), static_cast<double>(g.y_m), static_cast<double>(g.theta_rad)});
  }
  // A watched replay (real time by default) stops on SIGINT/SIGTERM with its summary, as a live node does; with
  // --view-wait it starts once a viewer has subscribed.
  void wait_for_viewer() {
    if (!view) return;
    catch_stop_signals();
    if (!c.view_wait) return;
    std::fprintf(stderr, "estimator_node: waiting for a viewer\n");
    node::wait_for_viewer(*view, [] { return g_stop_signal.load() != 0; });
  }

  hal::lcm::InputConfig lcm_input_config(unsigned counter_bits) const {
    hal::lcm::InputConfig ic;
    ic.channels = c.channels;
    ic.wheel_counter_bits = counter_bits;
    ic.max_ranges = static_cast<std::size_t>(kMaxBeams);
    return ic;
  }

  // Rejected by the transports (the pipeline adds the HAL's and its own).
  std::uint32_t transport_rejects() const {
    std::uint64_t n = 0;
    if (can_input) n += can_input->rejects().total() + can_input->scans().rejects().total();
    if (lcm_inputs) n += lcm_inputs->rejects().total();
    return saturate(n);
  }

  void refresh(std::uint32_t transport_bits) {
    if (lcm_inputs && lcm_inputs->rejects().total() != lcm_rejects_seen) {
      lcm_rejects_seen = lcm_inputs->rejects().total();
      transport_bits |= hal::status::kLcmDecodeError;
    }
    pipeline->refresh(transport_bits, transport_rejects());
  }

  est_lcm::status_t status_message(const hal::Estimate& e) const {
    est_lcm::status_t s{};
    s.stamp_ns = e.stamp_ns;
    s.status_word = static_cast<std::int32_t>(e.status);
    const est::loop::LoopCounters& lc = pipeline->loop_counters();
    s.steps = std::int64_t{lc.predictions} + lc.corrections;
    s.deadline_overruns = lc.overruns;
    const hal::FaultCounters f = pipeline->gate().faults();
    for (std::size_t i = 0; i < hal::kFaultCount; ++i) s.input_faults.push_back(f.count[i]);
    if (can_input) {
      for (std::uint32_t v : can_input->rejects().count) s.can_frame_rejects.push_back(v);
      for (std::uint32_t v : can_input->scans().rejects().count) s.can_scan_rejects.push_back(v);
    }
    s.num_input_faults = static_cast<std::int16_t>(s.input_faults.size());
    s.num_can_frame_rejects = static_cast<std::int16_t>(s.can_frame_rejects.size());
    s.num_can_scan_rejects = static_cast<std::int16_t>(s.can_scan_rejects.size());
    return s;
  }

  int run() {
    const auto wall_start = std::chrono::steady_clock::now();
    std::fprintf(stderr, "estimator_node: initial belief: %s\n", initial_belief(c.spec).c_str());
    int rc = 0;
    if (!c.replay_path.empty())
      rc = run_replay_lcm();
    else if (!c.replay_can_path.empty())
      rc = run_replay_can();
    else
      rc = run_live();
    stop_signal = g_stop_signal.load();
    if (receiver) udp_drops_at_end = udp_receive_drops();
    pipeline->flush();
    outputs.final_status();
    if (view) view->stop();
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return rc;
  }

  int run_replay_lcm() {
    hal::lcm::LcmLogReader in(c.replay_path);
    if (!in.good()) {
      std::fprintf(stderr, "estimator_node: cannot read %s\n", c.replay_path.c_str());
      return 1;
    }
    // memq: the backend's own decoding and checks, driven one message at a time.
    lcm_in = std::make_unique<::lcm::LCM>("memq://");
    stamper = std::make_unique<hal::Forward<hal::SensorPort, StampHook>>(pipeline->input(), StampHook{&stamp_clock});
    lcm_inputs = std::make_unique<hal::lcm::LcmInputs>(*lcm_in, lcm_input_config(c.lcm_wheel_counter_bits), *stamper);
    refresh(0);
    wait_for_viewer();
    Pacer pacer(c.replay_speed);
    hal::lcm::LcmLogEvent ev;
    while (g_stop_signal.load() == 0 && in.next(ev)) {
      ++log_events;
      pacer.at(ev.timestamp_us * 1000);  // the log's receive time, us
      if (view && ev.channel == c.channels.ground_truth) view_truth(ev.data.data(), ev.data.size());
      if (!lcm_inputs->is_input_channel(ev.channel)) continue;
      ++log_inputs;
      lcm_in->publish(ev.channel, ev.data.data(), static_cast<unsigned>(ev.data.size()));
      lcm_in->handle();
      refresh(0);
      feed_view();
    }
    log_problems = in.problems_total();
    if (in.refused() || in.events() == 0) {  // nothing to replay: say why and fail
      std::fprintf(stderr, "estimator_node: %s\n", hal::lcm::log_refusal(in, c.replay_path).what());
      return 2;
    }
    in.print_problems(stderr, "estimator_node: warning", c.replay_path);
    return 0;
  }

  int run_replay_can() {
    std::ifstream in(c.replay_can_path);
    if (!in) {
      std::fprintf(stderr, "estimator_node: cannot read %s\n", c.replay_can_path.c_str());
      return 1;
    }
    scans = std::make_unique<hal::can::ScanReassembler<static_cast<std::size_t>(kMaxBeams)>>();
    can_input = std::make_unique<hal::can::CanInput>(*scans, pipeline->input());
    refresh(0);
    wait_for_viewer();
    Pacer pacer(c.replay_speed);
    std::string line;
    std::uint64_t number = 0;
    while (g_stop_signal.load() == 0 && std::getline(in, line)) {
      ++number;
      hal::can::CanFrame frame;
      TimeNs stamp = 0;
      const hal::can::CandumpStatus st = hal::can::parse_candump_line(line.data(), line.size(), frame, stamp);
      if (st == hal::can::CandumpStatus::blank) continue;
      ++log_events;
      if (st != hal::can::CandumpStatus::ok) {
        ++candump_rejects;
        if (candump_rejects <= 5)
          std::fprintf(stderr, "estimator_node: %s:%llu: %s, line skipped\n", c.replay_can_path.c_str(),
                       static_cast<unsigned long long>(number), hal::can::to_string(st));
        continue;
      }
      ++log_inputs;
      pacer.at(stamp);
      stamp_clock.now = stamp;
      can_input->on_frame(frame, stamp);
      can_input->poll(stamp);
      refresh(0);
      feed_view();
    }
    return 0;
  }

  static void catch_stop_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
  }

  int run_live() {
    catch_stop_signals();

    if (c.lcm_input) {
      // The inputs go udpm -> the receiver's thread -> its bounded queue -> memq -> the backend's own decoding
      // (as a replay feeds them), so the loop's pace never decides what LCM or the kernel loses.
      lcm_in = std::make_unique<::lcm::LCM>("memq://");
      lcm_inputs = std::make_unique<hal::lcm::LcmInputs>(
          *lcm_in,
          lcm_input_config(c.can_interface.empty() ? c.lcm_wheel_counter_bits : hal::can::kCanWheelCounterBits),
          alignment ? static_cast<hal::SensorPort&>(*alignment) : pipeline->input());
      std::vector<std::string> channels = lcm_inputs->input_channels();
      if (view) channels.push_back(c.channels.ground_truth);
      receiver = std::make_unique<LcmReceiver>(c.lcm_url, channels);
      if (!receiver->good()) {
        std::fprintf(stderr, "estimator_node: cannot open LCM %s\n", c.lcm_url.c_str());
        return 1;
      }
    }
    // The outputs on an instance of their own (publishing from this thread while the receiver's handles in its own).
    {
      lcm_out = std::make_unique<::lcm::LCM>(c.lcm_out_url);
      if (!lcm_out->good()) {
        std::fprintf(stderr, "estimator_node: cannot open LCM %s for the outputs\n", c.lcm_out_url.c_str());
        return 1;
      }
    }
    ::lcm::LCM* out = lcm_out.get();
    lcm_outputs = std::make_unique<hal::lcm::LcmOutputs>(*out, c.channels);
    outputs.lcm = lcm_outputs.get();

    if (!c.can_interface.empty()) {
      hal::socketcan::Config bc;
      bc.interface = c.can_interface;
      bc.receive_ids.assign(std::begin(hal::can::dbc::kInputIds), std::end(hal::can::dbc::kInputIds));
      bc.receive_buffer_bytes = c.can_receive_buffer_bytes;
      bus = std::make_unique<hal::socketcan::SocketCanBus>(bc);
      if (!bus->open())
        std::fprintf(stderr, "estimator_node: %s: %s (retrying)\n", c.can_interface.c_str(), bus->last_error().c_str());
      scans = std::make_unique<hal::can::ScanReassembler<static_cast<std::size_t>(kMaxBeams)>>();
      can_input = std::make_unique<hal::can::CanInput>(*scans, pipeline->input());
      if (c.can_out) {
        can_sink = std::make_unique<hal::can::CanEstimateSink>(*bus);
        outputs.can = can_sink.get();
      }
    }

    std::fprintf(stderr, "estimator_node: running (%s%s%s%s)\n", c.can_interface.empty() ? "" : "can ",
                 c.can_interface.c_str(), c.lcm_input ? " lcm " : "", c.lcm_input ? c.lcm_url.c_str() : "");
    if (receiver) receiver->start();
    if (c.live_speed != 1.0)
      std::fprintf(stderr, "estimator_node: the stream's time runs %gx the wall clock (--live-speed)\n", c.live_speed);
    const TimeNs end_ns = c.duration_s > 0.0 ? monotonic.now_ns() + static_cast<TimeNs>(c.duration_s * 1.0e9) : 0;
    hal::socketcan::RxFrame frames[64];
    while (g_stop_signal.load() == 0) {
      pollfd fds[2];
      nfds_t n = 0;
      if (bus && bus->is_open()) fds[n++] = {bus->fd(), POLLIN, 0};
      if (receiver) fds[n++] = {receiver->wake_fd(), POLLIN, 0};
      ::poll(fds, n, 10);
      const TimeNs now = monotonic.now_ns();
      if (end_ns != 0 && now >= end_ns) break;
      if (bus) {
        bus->service(now);
        // Bounded: at most 16 reads of 64 frames per wake-up, so LCM and the stop signal are never starved.
        for (int batch = 0; batch < 16; ++batch) {
          const std::size_t got = bus->receive(frames, 64);
          for (std::size_t i = 0; i < got; ++i) {
            refresh(bus->take_status());
            can_input->on_frame(frames[i].frame, frames[i].stamp_ns);
          }
          if (got < 64) break;
        }
        can_input->poll(now);
      }
      if (receiver) {
        refresh(bus ? bus->take_status() : 0u);
        receiver->clear_wake();
        // Bounded like the CAN reads: at most one queue's worth per wake-up.
        for (std::size_t k = 0; k < receiver->capacity() && hand_one(); ++k) refresh(bus ? bus->take_status() : 0u);
      }
      feed_view();
    }
    if (receiver) {  // what was received is handed over or counted as dropped, never left behind
      receiver->stop();
      while (hand_one()) refresh(0);
    }
    return 0;
  }

  // The oldest queued LCM message through the backend's decoding (or to the view, the ground truth); false if none.
  bool hand_one() {
    if (!receiver->pop(raw)) return false;
    const std::string& channel = receiver->channels()[raw.channel];
    if (view && channel == c.channels.ground_truth) {
      view_truth(raw.bytes.data(), raw.size);
      return true;
    }
    const TimeNs wait = monotonic_wall_ns() - raw.receive_ns;
    if (wait > worst_queue_wait_ns) worst_queue_wait_ns = wait;
    if (alignment) alignment->set_arrival_ns(monotonic.at(raw.receive_ns));
    lcm_in->publish(channel, raw.bytes.data(), static_cast<unsigned>(raw.size));
    lcm_in->handle();
    return true;
  }
  static TimeNs monotonic_wall_ns() { return hal::socketcan::monotonic_now_ns(); }

  void print_summary(std::FILE* f) const {
    const est::loop::LoopCounters& lc = pipeline->loop_counters();
    std::fprintf(f, "estimator_node summary (%s%s)\n", replay ? "replay" : "live",
                 stop_signal == SIGINT ? ", stopped by SIGINT" : stop_signal == SIGTERM ? ", stopped by SIGTERM" : "");
    std::fprintf(f, "  map: %s; estimator: %s\n", maps->view.description.c_str(), pipeline->description().c_str());
    std::fprintf(f, "  initial belief: %s\n", initial_belief(c.spec).c_str());
    if (replay)
      std::fprintf(f, "  log: events=%llu inputs=%llu problems=%llu wall_s=%.3f\n",
                   static_cast<unsigned long long>(log_events), static_cast<unsigned long long>(log_inputs),
                   static_cast<unsigned long long>(log_problems), wall_s);
    else
      std::fprintf(f, "  run: wall_s=%.3f live_speed=%g\n", wall_s, c.live_speed);
    if (alignment && alignment->aligned())
      std::fprintf(f, "  stamps: aligned at the first message on %s, offset_s=%.6f streams_left=%llu realigned=%llu\n",
                   alignment->first_channel().c_str(), static_cast<double>(alignment->offset_ns()) * 1.0e-9,
                   static_cast<unsigned long long>(alignment->streams_left()),
                   static_cast<unsigned long long>(alignment->realigned()));
    std::string kinds, stale;
    for (const est::loop::InputKindInfo& k : est::loop::kInputKinds) {
      kinds += std::string(" ") + k.name + "=" + std::to_string(to_loop[est::loop::index_of(k.kind)]);
      if (pipeline->inputs().has(k.kind))
        stale += std::string(" ") + k.name + "=" + std::to_string(lc.of(k.kind).stale);
    }
    std::fprintf(f, "  inputs:%s (validated, handed to the loop)\n", kinds.c_str());
    std::fprintf(f,
                 "  loop: inputs=%u too_old=%u queue_full=%u rejected=%u predictions=%u corrections=%u degenerate=%u "
                 "overruns=%u worst_step_us=%.1f unused=%u\n",
                 lc.inputs, lc.too_old, lc.queue_full, lc.rejected, lc.predictions, lc.corrections, lc.degenerate,
                 lc.overruns, static_cast<double>(lc.worst_step_ns) / 1000.0, lc.unused);
    std::fprintf(f, "  stale outputs (by input kind used):%s\n", stale.c_str());
    std::fprintf(f, "  estimates: published=%llu nonfinite_held=%u\n", static_cast<unsigned long long>(outputs.count()),
                 pipeline->nonfinite_estimates());
    std::fprintf(f, "  rejects: total=%u\n", rejects_total());
    pipeline->gate().for_each_sensor([&](const char* name, const hal::FaultCounters& fc) {
      std::fprintf(f, "  rejects.%s:%s\n", name, reason_list<hal::Fault>(fc).c_str());
    });
    std::fprintf(f, "  rejects.loop_port:%s\n", reason_list<hal::LoopPortReject>(pipeline->port_rejects()).c_str());
    if (const est::loop::SlamAssociationCounters* s = pipeline->slam_counters())
      std::fprintf(f,
                   "  slam: landmarks=%d tentative_landmarks=%d frames=%u features=%u associated=%u created=%u "
                   "discarded=%u beyond_range=%u held_tentative=%u update_refused=%u insert_refused=%u map_full=%u "
                   "tentative_full=%u bad_input=%u tentative_forgotten=%u\n",
                   pipeline->slam_landmarks(), pipeline->slam_tentative_landmarks(), s->frames, s->features(),
                   s->associated, s->created, s->discarded, s->beyond_range, s->tentative, s->update_refused,
                   s->insert_refused, s->map_full, s->tentative_full, s->bad_input, s->tentative_forgotten);
    if (const est::loop::JointAssociationCounters* j = pipeline->joint_counters())
      std::fprintf(f,
                   "  jcbb: frames=%u features=%u paired=%u unpaired=%u ambiguous_frames=%u lone_refused=%u "
                   "node_cap_hits=%u split_frames=%u candidates_dropped=%u reopenings=%u\n",
                   j->frames, j->features, j->paired, j->unpaired, j->ambiguous_frames, j->lone_refused,
                   j->node_cap_hits, j->split_frames, j->candidates_dropped, pipeline->ekf_reopenings());
    if (pipeline->inputs().has(est::loop::InputKind::scan)) {
      const auto& beams = pipeline->gate().scan().beams();  // readings refused inside scans the gate passed
      std::fprintf(f, "  beams.scan: nan=%u below_min=%u\n", beams.not_a_number, beams.below_min);
    }
    if (lcm_inputs)
      std::fprintf(f, "  rejects.lcm:%s accepted=%llu\n", reason_list<hal::lcm::LcmReject>(lcm_inputs->rejects()).c_str(),
                   static_cast<unsigned long long>(lcm_inputs->accepted()));
    if (receiver) print_queue(f);
    if (receiver) {
      // Live over udpm: what the kernel dropped before LCM saw it (a full receive buffer: the node fell behind).
      if (const std::optional<std::uint64_t> drops = udp_drops_at_end)
        std::fprintf(f, "  lcm_udp: kernel_drops=%llu (datagrams dropped on a full receive buffer)\n",
                     static_cast<unsigned long long>(*drops));
    }
    if (can_input) {
      std::fprintf(f, "  rejects.can_frame:%s accepted=%u\n",
                   reason_list<hal::can::FrameReject>(can_input->rejects()).c_str(), can_input->frames_accepted());
      std::fprintf(f, "  rejects.can_scan:%s completed=%u\n",
                   reason_list<hal::can::ScanReject>(can_input->scans().rejects()).c_str(),
                   can_input->scans().scans_completed());
    }
    if (!c.replay_can_path.empty())
      std::fprintf(f, "  rejects.candump_lines: %llu\n", static_cast<unsigned long long>(candump_rejects));
    if (bus) {
      const hal::socketcan::Counters& b = bus->counters();
      std::fprintf(f,
                   "  can: rx_frames=%llu tx_frames=%llu tx_failed=%llu rx_dropped=%llu error_frames=%llu "
                   "bus_off=%llu link_lost=%llu reconnects=%llu\n",
                   static_cast<unsigned long long>(b.rx_frames), static_cast<unsigned long long>(b.tx_frames),
                   static_cast<unsigned long long>(b.tx_failed), static_cast<unsigned long long>(b.rx_dropped),
                   static_cast<unsigned long long>(b.error_frames), static_cast<unsigned long long>(b.bus_off_events),
                   static_cast<unsigned long long>(b.link_lost), static_cast<unsigned long long>(b.reconnects));
    }
    if (lcm_outputs)
      std::fprintf(f, "  lcm_out: publish_failures=%llu\n",
                   static_cast<unsigned long long>(lcm_outputs->publish_failures()));
    if (out_log)
      std::fprintf(f, "  out_log: events=%llu failures=%llu\n", static_cast<unsigned long long>(out_log->events()),
                   static_cast<unsigned long long>(out_log->failures()));
    if (candump)
      std::fprintf(f, "  out_can: frames=%llu\n", static_cast<unsigned long long>(candump->frames()));
    if (view) std::fprintf(f, "  view: %s\n", view_counters_line(*view).c_str());
    if (record_log)
      std::fprintf(f, "  record_log: events=%llu failures=%llu\n", static_cast<unsigned long long>(record_log->events()),
                   static_cast<unsigned long long>(record_log->failures()));
  }

  // received = handed + dropped (full: the oldest gave way; oversize: larger than a slot, as no valid input is).
  void print_queue(std::FILE* f) const {
    const RawQueueCounters q = receiver->counters();
    std::string by_channel;
    for (std::size_t i = 0; i < receiver->channels().size(); ++i)
      by_channel += (i == 0 ? "" : " ") + receiver->channels()[i] + "=" +
                    std::to_string(q.dropped_full[i] + q.dropped_oversize[i]);
    std::fprintf(f,
                 "  lcm_queue: capacity=%zu received=%llu handed=%llu dropped=%llu (by channel %s) oversize=%llu "
                 "high_water=%zu worst_wait_ms=%.1f\n",
                 receiver->capacity(), static_cast<unsigned long long>(RawQueueCounters::sum(q.received)),
                 static_cast<unsigned long long>(RawQueueCounters::sum(q.handed)),
                 static_cast<unsigned long long>(RawQueueCounters::sum(q.dropped_full) +
                                                 RawQueueCounters::sum(q.dropped_oversize)),
                 by_channel.c_str(), static_cast<unsigned long long>(RawQueueCounters::sum(q.dropped_oversize)),
                 q.high_water, static_cast<double>(worst_queue_wait_ns) * 1.0e-6);
  }

  std::uint32_t rejects_total() const {
    return saturate(std::uint64_t{transport_rejects()} + pipeline->gate().faults().total() +
                    pipeline->port_rejects().total() + candump_rejects);
  }

  NodeConfig c;
  bool replay;
  MonotonicClock monotonic;
  StampClock stamp_clock;
  FrozenClock frozen;
  std::unique_ptr<LoadedMaps> maps;
  NodeOutputs outputs;
  std::unique_ptr<EstimatorPipeline> pipeline;
  std::uint64_t to_loop[est::loop::kInputKindCount] = {};
  std::unique_ptr<hal::Forward<hal::ValidatedSensorPort, CountHook>> counter;
  std::unique_ptr<LogWriter> record_log, out_log;
  std::unique_ptr<hal::Forward<hal::ValidatedSensorPort, SenderTimeRecorder>> recorder;
  std::unique_ptr<CandumpWriter> candump;
  std::unique_ptr<hal::can::CanEstimateSink> candump_sink;
  std::unique_ptr<hal::Forward<hal::SensorPort, StampHook>> stamper;
  std::unique_ptr<StampAlignment> alignment;  // live LCM inputs onto the node's clock (--stamps align)
  std::unique_ptr<view::LiveView> view;        // --view
  // The LCM instances outlive the backend objects that subscribe on them (members are destroyed in reverse).
  std::unique_ptr<::lcm::LCM> lcm_in, lcm_out;
  std::unique_ptr<hal::lcm::LcmInputs> lcm_inputs;
  std::unique_ptr<hal::lcm::LcmOutputs> lcm_outputs;
  std::unique_ptr<LcmReceiver> receiver;  // live LCM inputs: the udpm instance, its thread and queue
  RawMessage raw;                         // the message being handed over
  TimeNs worst_queue_wait_ns = 0;
  std::unique_ptr<hal::socketcan::SocketCanBus> bus;
  std::unique_ptr<hal::can::ScanReassembler<static_cast<std::size_t>(kMaxBeams)>> scans;
  std::unique_ptr<hal::can::CanInput> can_input;
  std::unique_ptr<hal::can::CanEstimateSink> can_sink;
  std::uint32_t lcm_rejects_seen = 0;
  std::uint64_t log_events = 0, log_inputs = 0, log_problems = 0, candump_rejects = 0;
  double wall_s = 0.0;
  int stop_signal = 0;
  std::optional<std::uint64_t> udp_drops_at_end;  // live LCM: the kernel's drops on the node's sockets
};

Node::Node(const NodeConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Node::~Node() = default;
int Node::run() { return impl_->run(); }
void Node::print_summary(std::FILE* f) const { impl_->print_summary(f); }
const EstimatorPipeline& Node::pipeline() const { return *impl_->pipeline; }
std::uint64_t Node::inputs_to_loop(est::loop::InputKind k) const { return impl_->to_loop[est::loop::index_of(k)]; }
std::uint64_t Node::estimates() const { return impl_->outputs.count(); }
std::uint32_t Node::rejects_total() const { return impl_->rejects_total(); }
std::uint64_t Node::log_events() const { return impl_->log_events; }
std::uint64_t Node::log_inputs() const { return impl_->log_inputs; }
std::uint64_t Node::log_problems() const { return impl_->log_problems; }

}  // namespace node

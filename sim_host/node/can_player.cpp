// can_player: plays an LCM sensor log (est_lcm encoder_ticks_t, steering_t, twist_t, odometry_t, range_scan_t, as
// sim_host records them or estimator_node --record-inputs writes them) as hal/can/estimator.dbc frames: onto a CAN
// interface (--can), paced by the messages' stamp_ns (--speed 1 is real time, 0 as fast as the bus takes them; the
// receiver stamps them with its own receive time, as a real bus would), or into a candump log (--write), each
// frame stamped with its message's stamp_ns, for estimator_node --replay-can and the board image. Encoder counters
// are cut to the bus's 16 bits; landmark sightings have no frame and are skipped (counted). --clock-offset NS sends
// each message at CLOCK_MONOTONIC stamp_ns + NS instead, so a caller that chose NS maps the receiver's stamps back
// onto the log's time exactly (sim_host run --live --can).
#include <poll.h>
#include <time.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hal/can/candump.hpp"
#include "hal/can/sample_frames.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/socketcan/socketcan_bus.hpp"

namespace {

using hal::TimeNs;

void sleep_until(TimeNs t_ns) {
  timespec ts{static_cast<time_t>(t_ns / hal::kNsPerS), static_cast<long>(t_ns % hal::kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
  }
}

// Where the frames go: a bus, or a candump file.
struct Output {
  hal::socketcan::SocketCanBus* bus = nullptr;
  std::FILE* file = nullptr;
  std::uint64_t frames = 0, failed = 0;

  // A full kernel queue is waited out (up to 200 ms per frame), as a CAN controller would hold the frame.
  void send(const hal::can::CanFrame& f, TimeNs stamp_ns) {
    if (file != nullptr) {
      char line[hal::can::kCandumpLineMax];
      const std::size_t n = hal::can::format_candump_line(f, stamp_ns, "can0", line);
      if (std::fwrite(line, 1, n, file) == n) ++frames; else ++failed;
      return;
    }
    for (int attempt = 0; attempt < 1000; ++attempt) {
      if (bus->send(f)) {
        ++frames;
        return;
      }
      pollfd p{bus->fd(), POLLOUT, 0};
      ::poll(&p, 1, 1);
      if (attempt > 0 && attempt % 200 == 0) bus->service(hal::socketcan::monotonic_now_ns());
    }
    ++failed;
  }
};

// Receives each sensor message of the log as its raw sample and sends its frames.
class Player final : public hal::PortImplementation<Player, hal::SensorPort> {
 public:
  Player(Output& out, double speed, double start_delay_s, const TimeNs* clock_offset_ns)
      : out_(out), speed_(speed), delay_s_(start_delay_s), offset_ns_(clock_offset_ns) {}

  template <typename Raw>
  void handle(const Raw& s) {
    const std::size_t n = encoder_.encode(s, frames_.data(), frames_.size());
    if (n == 0) {
      ++skipped_;
      return;
    }
    pace(s.stamp_ns);
    for (std::size_t i = 0; i < n; ++i) out_.send(frames_[i], s.stamp_ns);
    ++messages_;
  }
  std::uint64_t messages() const { return messages_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  void pace(TimeNs stamp) {
    if (out_.file != nullptr) return;
    if (offset_ns_ != nullptr) {
      sleep_until(stamp + *offset_ns_);
      return;
    }
    if (!started_) {
      started_ = true;
      first_stamp_ = stamp;
      wall0_ = hal::socketcan::monotonic_now_ns() + static_cast<TimeNs>(delay_s_ * 1e9);
    }
    if (speed_ > 0.0) sleep_until(wall0_ + static_cast<TimeNs>(static_cast<double>(stamp - first_stamp_) / speed_));
  }

  Output& out_;
  double speed_, delay_s_;
  const TimeNs* offset_ns_;
  hal::can::SampleFrames encoder_;
  std::vector<hal::can::CanFrame> frames_ =
      std::vector<hal::can::CanFrame>(hal::can::scan_frame_count(hal::can::kMaxScanRanges));
  bool started_ = false;
  TimeNs first_stamp_ = 0, wall0_ = 0;
  std::uint64_t messages_ = 0, skipped_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"can_player: play an LCM sensor log as estimator.dbc frames, onto a CAN interface or into a candump log"};
  std::string log_path, iface = "vcan0", write_path;
  double speed = 1.0;
  double start_delay_s = 0.0;
  hal::lcm::InputConfig ic;
  app.add_option("log", log_path, "LCM log to play (lcm-logger format)")->required()->check(CLI::ExistingFile);
  app.add_option("--can", iface, "CAN interface")->capture_default_str();
  app.add_option("--write", write_path, "write the frames to this candump log instead of a bus (no pacing)");
  app.add_option("--speed", speed, "pacing by the messages' stamp_ns: 1 real time, 2 twice as fast, 0 no pacing")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--start-delay", start_delay_s, "wait this long before the first frame (s)")->capture_default_str();
  TimeNs clock_offset_ns = 0;
  CLI::Option* clock_offset =
      app.add_option("--clock-offset", clock_offset_ns,
                     "send each message at CLOCK_MONOTONIC stamp_ns + NS (real time on a known offset; instead of "
                     "--speed and --start-delay)");
  app.add_option("--wheel-counter-bits", ic.wheel_counter_bits, "width of the log's encoder counters")->capture_default_str();
  app.add_option("--ch-wheel-ticks", ic.channels.wheel_ticks, "LCM channel of the encoder ticks")->capture_default_str();
  app.add_option("--ch-steering", ic.channels.steering, "LCM channel of the steering")->capture_default_str();
  app.add_option("--ch-twist", ic.channels.twist, "LCM channel of the twists")->capture_default_str();
  app.add_option("--ch-odometry", ic.channels.odometry, "LCM channel of the odometry")->capture_default_str();
  app.add_option("--ch-scan", ic.channels.range_scan, "LCM channel of the scans")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  hal::lcm::LcmLogReader log(log_path);
  if (!log.good()) {
    std::fprintf(stderr, "can_player: cannot read %s\n", log_path.c_str());
    return 1;
  }
  Output out;
  std::unique_ptr<hal::socketcan::SocketCanBus> bus;
  if (!write_path.empty()) {
    out.file = std::fopen(write_path.c_str(), "w");
    if (out.file == nullptr) {
      std::fprintf(stderr, "can_player: cannot create %s\n", write_path.c_str());
      return 1;
    }
  } else {
    hal::socketcan::Config bc;
    bc.interface = iface;
    bc.receive_error_frames = false;
    bus = std::make_unique<hal::socketcan::SocketCanBus>(bc);
    if (!bus->open()) {
      std::fprintf(stderr, "can_player: %s: %s\n", iface.c_str(), bus->last_error().c_str());
      return 1;
    }
    out.bus = bus.get();
  }
  if (clock_offset->count() > 0 && !write_path.empty()) {
    std::fprintf(stderr, "can_player: --clock-offset paces a bus, not --write\n");
    return 2;
  }
  Player player(out, speed, start_delay_s, clock_offset->count() > 0 ? &clock_offset_ns : nullptr);
  ic.max_ranges = hal::can::kMaxScanRanges;
  ::lcm::LCM memq("memq://");
  hal::lcm::LcmInputs inputs(memq, ic, player);
  std::uint64_t undecodable = 0;
  hal::lcm::LcmLogEvent ev;
  while (log.next(ev)) {
    if (!inputs.is_input_channel(ev.channel)) continue;
    const std::uint64_t before = inputs.rejects().total();
    memq.publish(ev.channel, ev.data.data(), static_cast<unsigned>(ev.data.size()));
    memq.handle();
    if (inputs.rejects().total() != before) ++undecodable;
  }
  if (out.file != nullptr) std::fclose(out.file);
  if (log.events() == 0) {
    std::fprintf(stderr, "can_player: %s\n", hal::lcm::log_refusal(log, log_path).what());
    return 2;
  }
  log.print_problems(stderr, "can_player: warning", log_path);
  std::fprintf(stderr, "can_player: messages=%llu frames=%llu send_failed=%llu skipped=%llu undecodable=%llu\n",
               static_cast<unsigned long long>(player.messages()), static_cast<unsigned long long>(out.frames),
               static_cast<unsigned long long>(out.failed), static_cast<unsigned long long>(player.skipped()),
               static_cast<unsigned long long>(undecodable));
  return out.failed == 0 ? 0 : 1;
}

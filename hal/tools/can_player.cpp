// can_player: plays an LCM sensor log (est_lcm encoder_ticks_t, steering_t, range_scan_t, as sim_host records them or
// estimator_node --record-inputs writes them) onto a CAN interface as hal/can/estimator.dbc frames: WHEEL_TICKS
// (counters cut to the bus's 16 bits), STEERING, and each scan split into SCAN_HEADER, SCAN_INFO and SCAN_DATA
// frames. Messages are paced by their stamp_ns (--speed 1 is real time, 0 as fast as the bus takes them); the
// receiver stamps them with its own receive time, as a real bus would.
#include <poll.h>
#include <time.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hal/can/messages.hpp"
#include "hal/can/scan_frames.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/socketcan/socketcan_bus.hpp"

namespace {

using hal::TimeNs;

void sleep_until(TimeNs t_ns) {
  timespec ts{static_cast<time_t>(t_ns / hal::kNsPerS), static_cast<long>(t_ns % hal::kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
  }
}

struct Player {
  hal::socketcan::SocketCanBus& bus;
  std::uint64_t frames = 0, failed = 0;

  // A full kernel queue is waited out (up to 200 ms per frame), as a CAN controller would hold the frame.
  void send(const hal::can::CanFrame& f) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      if (bus.send(f)) {
        ++frames;
        return;
      }
      pollfd p{bus.fd(), POLLOUT, 0};
      ::poll(&p, 1, 1);
      if (attempt > 0 && attempt % 200 == 0) bus.service(hal::socketcan::monotonic_now_ns());
    }
    ++failed;
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"can_player: play an LCM sensor log onto a CAN interface as estimator.dbc frames"};
  std::string log_path, iface = "vcan0";
  double speed = 1.0;
  double start_delay_s = 0.0;
  hal::lcm::Channels ch;
  app.add_option("log", log_path, "LCM log to play (lcm-logger format)")->required()->check(CLI::ExistingFile);
  app.add_option("--can", iface, "CAN interface")->capture_default_str();
  app.add_option("--speed", speed, "pacing by the messages' stamp_ns: 1 real time, 2 twice as fast, 0 no pacing")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--start-delay", start_delay_s, "wait this long before the first frame (s)")->capture_default_str();
  app.add_option("--ch-wheel-ticks", ch.wheel_ticks, "LCM channel of the encoder ticks")->capture_default_str();
  app.add_option("--ch-steering", ch.steering, "LCM channel of the steering")->capture_default_str();
  app.add_option("--ch-scan", ch.range_scan, "LCM channel of the scans")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  ::lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "can_player: cannot read %s\n", log_path.c_str());
    return 1;
  }
  hal::socketcan::Config bc;
  bc.interface = iface;
  bc.receive_error_frames = false;
  hal::socketcan::SocketCanBus bus(bc);
  if (!bus.open()) {
    std::fprintf(stderr, "can_player: %s: %s\n", iface.c_str(), bus.last_error().c_str());
    return 1;
  }
  Player player{bus};
  std::uint8_t wheel_counter = 0, steering_counter = 0, scan_id = 0;
  std::uint64_t messages = 0, skipped = 0;
  std::vector<hal::can::CanFrame> scan_frames(hal::can::scan_frame_count(hal::can::kMaxScanRanges));
  bool started = false;
  TimeNs first_stamp = 0, wall0 = 0;

  auto pace = [&](TimeNs stamp) {
    if (!started) {
      started = true;
      first_stamp = stamp;
      wall0 = hal::socketcan::monotonic_now_ns() + static_cast<TimeNs>(start_delay_s * 1e9);
    }
    if (speed > 0.0) sleep_until(wall0 + static_cast<TimeNs>(static_cast<double>(stamp - first_stamp) / speed));
  };

  while (const ::lcm::LogEvent* ev = log.readNextEvent()) {
    const std::size_t size = static_cast<std::size_t>(ev->datalen);
    if (ev->channel == ch.wheel_ticks) {
      est_lcm::encoder_ticks_t m{};
      hal::WheelTicks s;
      if (hal::lcm::decode_guarded(ev->data, size, m, 4) != hal::lcm::LcmReject::none ||
          hal::lcm::to_hal(m, static_cast<unsigned>(m.counter_bits), s) != hal::lcm::LcmReject::none || s.wheel_count < 2) {
        ++skipped;
        continue;
      }
      pace(s.stamp_ns);
      hal::can::WheelTicksMsg w;
      w.ticks_left = static_cast<std::uint16_t>(s.count[0] & 0xFFFFu);
      w.ticks_right = static_cast<std::uint16_t>(s.count[1] & 0xFFFFu);
      w.counter = wheel_counter;
      wheel_counter = static_cast<std::uint8_t>((wheel_counter + 1u) & 0x0Fu);
      hal::can::CanFrame f;
      if (hal::can::encode(w, f) != hal::can::CodecStatus::ok) {
        ++skipped;
        continue;
      }
      player.send(f);
    } else if (ev->channel == ch.steering) {
      est_lcm::steering_t m{};
      if (hal::lcm::decode_guarded(ev->data, size, m, 0) != hal::lcm::LcmReject::none) {
        ++skipped;
        continue;
      }
      pace(m.stamp_ns);
      hal::can::SteeringMsg s{m.angle_rad, steering_counter};
      steering_counter = static_cast<std::uint8_t>((steering_counter + 1u) & 0x0Fu);
      hal::can::CanFrame f;
      if (hal::can::encode(s, f) != hal::can::CodecStatus::ok) {
        ++skipped;
        continue;
      }
      player.send(f);
    } else if (ev->channel == ch.range_scan) {
      est_lcm::range_scan_t m{};
      hal::RangeScanView v;
      if (hal::lcm::decode_guarded(ev->data, size, m, static_cast<std::int64_t>(hal::can::kMaxScanRanges)) !=
              hal::lcm::LcmReject::none ||
          hal::lcm::to_hal(m, v) != hal::lcm::LcmReject::none) {
        ++skipped;
        continue;
      }
      pace(v.stamp_ns);
      const hal::can::ScanSplit split = hal::can::split_scan(v, scan_id, scan_frames.data(), scan_frames.size());
      scan_id = static_cast<std::uint8_t>((scan_id + 1u) & 0x0Fu);
      if (split.status != hal::can::CodecStatus::ok) {
        ++skipped;
        continue;
      }
      for (std::size_t i = 0; i < split.frames; ++i) player.send(scan_frames[i]);
    } else {
      continue;
    }
    ++messages;
  }
  std::fprintf(stderr, "can_player: messages=%llu frames=%llu send_failed=%llu skipped=%llu\n",
               static_cast<unsigned long long>(messages), static_cast<unsigned long long>(player.frames),
               static_cast<unsigned long long>(player.failed), static_cast<unsigned long long>(skipped));
  return player.failed == 0 ? 0 : 1;
}

#pragma once
// LCM log files the node writes itself (host only): estimates for --out, and the inputs it handed to the loop for
// --record-inputs. Event times are the messages' own stamps (microseconds), never the wall clock, so a log written
// from the same inputs is the same file, byte for byte.
#include <lcm/lcm-cpp.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/sensor_port.hpp"
#include "hal/time.hpp"
#include "hal/lcm/lcm_backend.hpp"

namespace hal::node {

class LogWriter {
 public:
  explicit LogWriter(const std::string& path);  // throws std::runtime_error when the file cannot be created
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  template <typename Message>
  void write(const std::string& channel, TimeNs stamp_ns, const Message& m) {
    const int n = m.getEncodedSize();
    buffer_.resize(static_cast<std::size_t>(n));
    m.encode(buffer_.data(), 0, n);
    write_raw(channel, stamp_ns, buffer_.data(), n);
  }
  void write_raw(const std::string& channel, TimeNs stamp_ns, const void* data, int size);
  std::uint64_t events() const { return events_; }
  std::uint64_t failures() const { return failures_; }

 private:
  ::lcm::LogFile file_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t events_ = 0;
  std::uint64_t failures_ = 0;
};

// A tee in front of the loop: writes each validated input as the est_lcm message a replay reads back (encoder
// increments as 32-bit cumulative counters, so the validator's unwrapping gives the same increments again), then
// passes it on.
class InputRecorder final : public ValidatedSensorPort {
 public:
  InputRecorder(LogWriter& log, const hal::lcm::Channels& channels, ValidatedSensorPort& next)
      : log_(log), channels_(channels), next_(next) {}

  void on_wheel_motion(const WheelTickDelta& delta) override;
  void on_steering(const SteeringSample& sample) override;
  void on_range_scan(const RangeScanView& scan) override;
  void on_landmarks(const LandmarkSightingView& sighting) override;

 private:
  LogWriter& log_;
  hal::lcm::Channels channels_;
  ValidatedSensorPort& next_;
  std::uint32_t cumulative_[kMaxWheels] = {};
};

}  // namespace hal::node

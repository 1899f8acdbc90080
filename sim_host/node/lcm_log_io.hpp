#pragma once
// Log files the node writes itself (host only): estimates for --out (LCM) and --out-can (candump), and the inputs
// it handed to the loop for --record-inputs. Event times are the messages' own stamps, never the wall clock, so a
// log written from the same inputs is the same file, byte for byte.
#include <cstdint>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hal/can/frame.hpp"
#include "hal/lcm/channels.hpp"
#include "hal/sensor_port.hpp"
#include "hal/time.hpp"

namespace node {

using hal::TimeNs;

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

// CAN frames to a candump log (hal/can/candump.hpp), each with the stamp set before it is sent.
class CandumpWriter final : public hal::can::CanTx {
 public:
  CandumpWriter(const std::string& path, std::string interface);  // throws std::runtime_error
  ~CandumpWriter();
  CandumpWriter(const CandumpWriter&) = delete;
  CandumpWriter& operator=(const CandumpWriter&) = delete;

  void set_stamp(TimeNs stamp_ns) { stamp_ns_ = stamp_ns; }
  bool send(const hal::can::CanFrame& frame) override;
  std::uint64_t frames() const { return frames_; }

 private:
  std::FILE* file_;
  std::string interface_;
  TimeNs stamp_ns_ = 0;
  std::uint64_t frames_ = 0;
};

// Writes each checked input as the est_lcm message a replay reads back, so that the replay's gate gives the same
// inputs again: encoder increments as 32-bit cumulative counters, odometry as the pose it was differenced from
// (both, for a bus's wrapping odometry, unwrapped to float positions: the same increments to rounding), the rest as
// they are. The hook of a hal::Forward in front of the loop.
class InputRecorder {
 public:
  InputRecorder(LogWriter& log, const hal::lcm::Channels& channels) : log_(&log), channels_(channels) {}

  void operator()(const hal::WheelTickDelta& d);
  void operator()(const hal::SteeringSample& s);
  void operator()(const hal::TwistSample& s);
  void operator()(const hal::OdometryDelta& d);
  void operator()(const hal::RangeScanView& s);
  void operator()(const hal::LandmarkSightingView& s);

 private:
  LogWriter* log_;
  hal::lcm::Channels channels_;
  std::uint32_t cumulative_[hal::kMaxWheels] = {};
  bool odometry_started_ = false;
  est::Pose2 odometry_;  // the unwrapped pose of a wrapping source
};

}  // namespace node

// Log files written by the node (node/lcm_log_io.hpp).
#include "node/lcm_log_io.hpp"

#include <stdexcept>

#include "hal/can/candump.hpp"
#include "hal/lcm/lcm_convert.hpp"

namespace node {

LogWriter::LogWriter(const std::string& path) : file_(path, "w") {
  if (!file_.good()) throw std::runtime_error("cannot create LCM log " + path);
}

void LogWriter::write_raw(const std::string& channel, TimeNs stamp_ns, const void* data, int size) {
  ::lcm::LogEvent e{};
  e.timestamp = stamp_ns / 1000;
  e.channel = channel;
  e.datalen = size;
  e.data = const_cast<void*>(data);  // LogFile::writeEvent only reads it
  if (file_.writeEvent(&e) == 0)
    ++events_;
  else
    ++failures_;
}

CandumpWriter::CandumpWriter(const std::string& path, std::string interface)
    : file_(std::fopen(path.c_str(), "w")), interface_(std::move(interface)) {
  if (file_ == nullptr) throw std::runtime_error("cannot create candump log " + path);
}

CandumpWriter::~CandumpWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

bool CandumpWriter::send(const hal::can::CanFrame& frame) {
  char line[hal::can::kCandumpLineMax];
  const std::size_t n = hal::can::format_candump_line(frame, stamp_ns_, interface_.c_str(), line);
  if (std::fwrite(line, 1, n, file_) != n) return false;
  ++frames_;
  return true;
}

void InputRecorder::operator()(const hal::WheelTickDelta& delta) {
  hal::WheelTicks counters;
  counters.stamp_ns = delta.stamp_ns;
  counters.wheel_count = delta.wheel_count;
  for (std::size_t w = 0; w < delta.wheel_count && w < hal::kMaxWheels; ++w) {
    cumulative_[w] += static_cast<std::uint32_t>(delta.ticks[w]);  // modulo 2^32, as a 32-bit counter wraps
    counters.count[w] = cumulative_[w];
  }
  log_->write(channels_.wheel_ticks, delta.stamp_ns, hal::lcm::to_lcm(counters, 32));
}

void InputRecorder::operator()(const hal::SteeringSample& s) {
  log_->write(channels_.steering, s.stamp_ns, hal::lcm::to_lcm(s));
}

void InputRecorder::operator()(const hal::TwistSample& s) { log_->write(channels_.twist, s.stamp_ns, hal::lcm::to_lcm(s)); }

void InputRecorder::operator()(const hal::OdometryDelta& d) {
  hal::OdometrySample s = d.source;
  if (s.wrap_m > 0.0f) {  // LCM's floats do not wrap: the pose integrated from the increments
    odometry_ = odometry_started_ ? est::compose(odometry_, d.increment) : s.pose;
    odometry_started_ = true;
    s.pose = odometry_;
    s.wrap_m = 0.0f;
  }
  log_->write(channels_.odometry, d.stamp_ns, hal::lcm::to_lcm(s));
}

void InputRecorder::operator()(const hal::RangeScanView& s) {
  log_->write(channels_.range_scan, s.stamp_ns, hal::lcm::to_lcm(s));
}

void InputRecorder::operator()(const hal::LandmarkSightingView& s) {
  log_->write(channels_.landmarks, s.stamp_ns, hal::lcm::to_lcm(s));
}

}  // namespace node

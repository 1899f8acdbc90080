// LCM log files written by the node (hal/tools/lcm_log_io.hpp).
#include "lcm_log_io.hpp"

#include <stdexcept>

#include "hal/lcm/lcm_convert.hpp"

namespace hal::node {

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

void InputRecorder::on_wheel_motion(const WheelTickDelta& delta) {
  WheelTicks counters;
  counters.stamp_ns = delta.stamp_ns;
  counters.wheel_count = delta.wheel_count;
  for (std::size_t w = 0; w < delta.wheel_count && w < kMaxWheels; ++w) {
    cumulative_[w] += static_cast<std::uint32_t>(delta.ticks[w]);  // modulo 2^32, as a 32-bit counter wraps
    counters.count[w] = cumulative_[w];
  }
  log_.write(channels_.wheel_ticks, delta.stamp_ns, hal::lcm::to_lcm(counters, 32));
  next_.on_wheel_motion(delta);
}

void InputRecorder::on_steering(const SteeringSample& sample) {
  log_.write(channels_.steering, sample.stamp_ns, hal::lcm::to_lcm(sample));
  next_.on_steering(sample);
}

void InputRecorder::on_range_scan(const RangeScanView& scan) {
  log_.write(channels_.range_scan, scan.stamp_ns, hal::lcm::to_lcm(scan));
  next_.on_range_scan(scan);
}

void InputRecorder::on_landmarks(const LandmarkSightingView& sighting) {
  log_.write(channels_.landmarks, sighting.stamp_ns, hal::lcm::to_lcm(sighting));
  next_.on_landmarks(sighting);
}

}  // namespace hal::node

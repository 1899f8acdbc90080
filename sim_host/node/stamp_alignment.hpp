#pragma once
// Live LCM inputs stamped on another clock (a log played by lcm-logplayer, a sender on another machine): one offset
// maps the sender's stamps onto the node's clock, measured at the first message of the stream, so that the HAL gate
// judges staleness against the node's clock while the relative timing of the sensors, which is all the loop uses,
// is kept to the nanosecond. A sender already on the node's clock (its first message passes the gate as sent) keeps
// its stamps (offset 0). The node's outputs are mapped back (to_sender): its estimates are in the sender's time, as
// a --replay of the same stream gives them. A node aligns one stream, at its pace: a stream that leaves the
// alignment for good (a log played again, a player paused or faster than 1x) is refused by the gate, stale or from
// the future, and said so once. While the stream settles (1 s of the node's time after its first message), a message that
// came markedly earlier than the first one implies shows that the first one was late (a busy host at 10x: 11 ms of
// wall time is the whole future margin): the offset is taken again from it (said once). Host only.
#include <cstdint>
#include <cstdio>
#include <string>

#include "hal/lcm/lcm_convert.hpp"
#include "hal/sample_timing.hpp"
#include "hal/sensor_port.hpp"
#include "hal/time.hpp"

namespace node {

using hal::TimeNs;

// A stamp moved by `by`; stamps come from the outside and may be anything: saturates instead of overflowing.
inline TimeNs shifted(TimeNs t, TimeNs by) {
  TimeNs r = 0;
  if (__builtin_add_overflow(t, by, &r)) return by > 0 ? INT64_MAX : INT64_MIN;
  return r;
}
// A sample with every stamp it carries moved by `by` (an odometry increment also carries the pose it came from).
template <typename Sample>
Sample shifted(Sample s, TimeNs by) {
  s.stamp_ns = shifted(s.stamp_ns, by);
  return s;
}
inline hal::OdometryDelta shifted(hal::OdometryDelta d, TimeNs by) {
  d.stamp_ns = shifted(d.stamp_ns, by);
  d.source.stamp_ns = shifted(d.source.stamp_ns, by);
  return d;
}

class StampAlignment final : public hal::PortImplementation<StampAlignment, hal::SensorPort> {
 public:
  // `limits`: the gate's (hal::TimingLimits); `clock`: the one the gate reads.
  StampAlignment(hal::Clock& clock, const hal::TimingLimits& limits, const hal::lcm::Channels& channels,
                 hal::SensorPort& next, std::FILE* say = stderr)
      : clock_(clock), limits_(limits), channels_(channels), next_(next), say_(say) {}

  template <typename Raw>
  void handle(const Raw& s) {
    const std::string& channel = channels_.*hal::lcm::LcmCodec<Raw>::channel;
    if (!aligned_)
      align(s.stamp_ns, channel);
    else
      settle(s.stamp_ns, channel);
    const Raw moved = shifted(s, offset_ns_);
    note_fit(moved.stamp_ns, channel);
    next_.on(moved);
  }

  // Live through a receive queue (node/lcm_receiver.hpp): when the next message arrived, on the node's clock. The
  // first message is aligned at its arrival rather than when the loop takes it: a loop busy at that moment (a step, a
  // descheduled thread) would otherwise place the stream late by that much, and the messages queued behind it, taken
  // in a burst, then look that much early (from the future: at 10x the gate allows 0.5 ms of wall time).
  void set_arrival_ns(TimeNs node_ns) { arrival_ns_ = node_ns; }

  bool aligned() const { return aligned_; }
  TimeNs offset_ns() const { return offset_ns_; }  // added to the sender's stamps
  TimeNs to_sender(TimeNs node_ns) const { return shifted(node_ns, -offset_ns_); }
  const std::string& first_channel() const { return first_channel_; }
  std::uint64_t streams_left() const { return streams_left_; }  // times the stream left the alignment for good
  std::uint64_t realigned() const { return realigned_; }  // times the offset was lowered while settling

 private:
  void align(TimeNs stamp_ns, const std::string& channel);
  void settle(TimeNs stamp_ns, const std::string& channel);
  void note_fit(TimeNs node_stamp_ns, const std::string& channel);

  hal::Clock& clock_;
  hal::TimingLimits limits_;
  hal::lcm::Channels channels_;
  hal::SensorPort& next_;
  std::FILE* say_;
  bool aligned_ = false;
  TimeNs offset_ns_ = 0;
  TimeNs arrival_ns_ = 0;  // 0: unknown, the clock's now
  bool settling_ = false;  // within the gate's window after a shifted first message
  TimeNs aligned_at_ns_ = 0;
  std::uint64_t realigned_ = 0;
  std::string first_channel_;
  hal::Fault misfit_ = hal::Fault::none;  // the gate's verdict on the messages since misfit_since_ns_ (stale, ahead)
  TimeNs misfit_since_ns_ = 0;            // node time of the first of them
  double misfit_by_s_ = 0.0;              // how far off the first of them was
  bool said_ = false;                     // once per departure
  std::uint64_t streams_left_ = 0;
};

}  // namespace node

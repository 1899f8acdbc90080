// Sender stamps onto the node's clock (node/stamp_alignment.hpp).
#include "node/stamp_alignment.hpp"

namespace node {

namespace {
double seconds(TimeNs ns) { return static_cast<double>(ns) * 1.0e-9; }
}  // namespace

void StampAlignment::align(TimeNs stamp_ns, const std::string& channel) {
  aligned_ = true;
  first_channel_ = channel;
  const TimeNs now = arrival_ns_ != 0 ? arrival_ns_ : clock_.now_ns();
  if (hal::SampleTiming(limits_).check(stamp_ns, now) == hal::Fault::none) {
    std::fprintf(say_, "estimator_node: sender stamps are on the node clock (first message on %s %.1f ms old): kept\n",
                 channel.c_str(), seconds(now - stamp_ns) * 1.0e3);
    return;
  }
  // The first message is put at the middle of the gate's window rather than at its edge (age 0), so that the stream
  // may run up to half the window late or early against it (the player's jitter, sensors with other latencies than
  // the first one's: 1 ms encoders and 12 ms scans in the simulator) before the gate rejects an input.
  const TimeNs middle_age = (limits_.max_age_ns - limits_.max_future_ns) / 2;
  offset_ns_ = shifted(now - middle_age, -stamp_ns);
  settling_ = true;
  aligned_at_ns_ = now;
  std::fprintf(say_,
               "estimator_node: aligned sender stamps to the node clock: offset %.6f s at the first message on %s "
               "(placed %.1f ms in the past)\n",
               seconds(offset_ns_), channel.c_str(), seconds(middle_age) * 1.0e3);
}

void StampAlignment::settle(TimeNs stamp_ns, const std::string& channel) {
  if (!settling_) return;
  const TimeNs now = arrival_ns_ != 0 ? arrival_ns_ : clock_.now_ns();
  // One second of the node's time (0.1 s of wall time at 10x) or the gate's window if longer: a host busy at the
  // start can hold up the first tens of messages, not only the first.
  const TimeNs settle_ns = limits_.max_age_ns > hal::kNsPerS ? limits_.max_age_ns : hal::kNsPerS;
  if (now - aligned_at_ns_ > settle_ns) {
    settling_ = false;
    return;
  }
  // Half the placement of slack: sensors' own latencies differ by a few ms (1 ms encoders, 12 ms scans in the
  // simulator), which must not move the alignment; a first message held up by tens of ms must.
  const TimeNs middle_age = (limits_.max_age_ns - limits_.max_future_ns) / 2;
  const TimeNs age = now - shifted(stamp_ns, offset_ns_);
  if (age >= middle_age / 2) return;
  offset_ns_ = shifted(now - middle_age, -stamp_ns);
  if (++realigned_ > 1) return;  // said once
  std::fprintf(say_,
               "estimator_node: re-aligned sender stamps at a message on %s that came %.1f ms earlier than the first "
               "one implied (the first was held up): offset %.6f s (inputs already taken may be refused as going "
               "back in time)\n",
               channel.c_str(), seconds(middle_age - age) * 1.0e3, seconds(offset_ns_));
}

void StampAlignment::note_fit(TimeNs node_stamp_ns, const std::string& channel) {
  const TimeNs now = clock_.now_ns();
  const hal::Fault f = hal::SampleTiming(limits_).check(node_stamp_ns, now);
  if (f != hal::Fault::stale && f != hal::Fault::from_future) {
    misfit_ = hal::Fault::none;
    said_ = false;
    return;
  }
  // One message off (a late one, a bad stamp) is the gate's business; every message off, the same way, for a whole
  // window of the gate is the stream gone from the alignment.
  if (f != misfit_) {
    misfit_ = f;
    misfit_since_ns_ = now;
    misfit_by_s_ = (static_cast<double>(now) - static_cast<double>(node_stamp_ns)) * 1.0e-9;
  }
  if (said_ || now - misfit_since_ns_ < limits_.max_age_ns + limits_.max_future_ns) return;
  // Re-aligning would hand the loop the new stream's inputs on a belief made of the old one (a log played again:
  // as if the robot had jumped back to its start), estimates that look valid and are not, their stamps going back.
  said_ = true;
  ++streams_left_;
  const bool behind = f == hal::Fault::stale;
  std::fprintf(say_,
               "estimator_node: sender stamps on %s left the alignment, %.3f s %s the node clock and staying (%s): "
               "these inputs are rejected as %s; the alignment holds for one stream at its pace, restart "
               "estimator_node to play another\n",
               channel.c_str(), behind ? misfit_by_s_ : -misfit_by_s_, behind ? "behind" : "ahead of",
               behind ? "a log played again? paused?" : "played faster than 1x?", hal::to_string(f));
}

}  // namespace node

#pragma once
// Pending inputs in timestamp order, statically sized: Capacity events, of which at most ScanSlots scans of at
// most KMax readings. Ties in time are ordered by kind (encoders, steering, scan, landmark), the features of one
// landmark sighting by their content (id, range, bearing, signature), and then by arrival, so the same inputs give
// the same order whatever order they arrived in within the reorder window (an EKF's result depends on the order
// features are fused in).
#include <cstdint>

#include "est/loop/inputs.hpp"

namespace est::loop {

enum class InputKind : std::uint8_t { wheel_ticks = 0, steering = 1, scan = 2, landmark = 3 };

struct QueuedInput {
  InputKind kind;
  TimeNs t_ns;
  std::uint32_t arrival;  // tie-break among equal (t, kind)
  WheelTicksInput ticks;
  SteeringInput steering;
  LandmarkInput landmark;
  std::uint8_t scan_slot;  // index into the scan slots for kind == scan
};

template <std::uint32_t Capacity, std::int32_t KMax, std::uint32_t ScanSlots>
class InputQueue {
  static_assert(Capacity >= 2u && ScanSlots >= 1u && ScanSlots <= 255u && KMax > 0, "bad queue capacities");

 public:
  struct ScanSlot {
    ScanLayout layout;
    float ranges[static_cast<std::uint32_t>(KMax)];
    bool used;
  };

  bool push(const WheelTicksInput& in) {
    QueuedInput q{};
    q.kind = InputKind::wheel_ticks;
    q.t_ns = in.t_ns;
    q.ticks = in;
    return insert(q);
  }
  bool push(const SteeringInput& in) {
    QueuedInput q{};
    q.kind = InputKind::steering;
    q.t_ns = in.t_ns;
    q.steering = in;
    return insert(q);
  }
  bool push(const LandmarkInput& in) {
    QueuedInput q{};
    q.kind = InputKind::landmark;
    q.t_ns = in.t_ns;
    q.landmark = in;
    return insert(q);
  }
  // Copies the readings. False when the queue or the scan slots are full, or the scan has more than KMax readings.
  bool push(const ScanInput& in) {
    if (in.layout.count <= 0 || in.layout.count > KMax || in.ranges == nullptr || count_ == Capacity) return false;
    std::uint32_t slot = 0;
    while (slot < ScanSlots && slots_[slot].used) ++slot;
    if (slot == ScanSlots) return false;
    slots_[slot].layout = in.layout;
    for (std::int32_t k = 0; k < in.layout.count; ++k) slots_[slot].ranges[k] = in.ranges[k];
    QueuedInput q{};
    q.kind = InputKind::scan;
    q.t_ns = in.t_ns;
    q.scan_slot = static_cast<std::uint8_t>(slot);
    if (!insert(q)) return false;
    slots_[slot].used = true;
    return true;
  }

  std::uint32_t size() const { return count_; }
  bool empty() const { return count_ == 0u; }
  const QueuedInput& front() const { return items_[0]; }
  TimeNs front_time() const { return items_[0].t_ns; }

  // The scan of a queued scan input, valid until pop() releases it.
  ScanInput scan(const QueuedInput& q) const {
    const ScanSlot& s = slots_[q.scan_slot];
    return {q.t_ns, s.layout, s.ranges};
  }

  // The first queued input of `kind` after the front one (queue order), or null: the loop borrows part of the next
  // encoder increment to bring the motion up to a scan's time.
  QueuedInput* next_of_kind(InputKind kind) {
    for (std::uint32_t i = 1; i < count_; ++i)
      if (items_[i].kind == kind) return &items_[i];
    return nullptr;
  }

  void pop() {
    if (count_ == 0u) return;
    if (items_[0].kind == InputKind::scan) slots_[items_[0].scan_slot].used = false;
    for (std::uint32_t i = 1; i < count_; ++i) items_[i - 1] = items_[i];
    --count_;
  }

 private:
  static bool before(const QueuedInput& a, const QueuedInput& b) {
    if (a.t_ns != b.t_ns) return a.t_ns < b.t_ns;
    if (a.kind != b.kind) return a.kind < b.kind;
    if (a.kind == InputKind::landmark) {
      const LandmarkInput& x = a.landmark;
      const LandmarkInput& y = b.landmark;
      if (x.id != y.id) return x.id < y.id;
      if (x.range_m != y.range_m) return x.range_m < y.range_m;  // a NaN one stays where it arrived (it is rejected)
      if (x.bearing_rad != y.bearing_rad) return x.bearing_rad < y.bearing_rad;
      if (x.signature != y.signature) return x.signature < y.signature;
    }
    return a.arrival < b.arrival;
  }

  bool insert(QueuedInput q) {
    if (count_ == Capacity) return false;
    q.arrival = arrivals_++;
    std::uint32_t i = count_;
    while (i > 0u && before(q, items_[i - 1])) {  // insertion from the back: O(1) for inputs arriving in order
      items_[i] = items_[i - 1];
      --i;
    }
    items_[i] = q;
    ++count_;
    return true;
  }

  QueuedInput items_[Capacity] = {};
  ScanSlot slots_[ScanSlots] = {};
  std::uint32_t count_ = 0;
  std::uint32_t arrivals_ = 0;
};

}  // namespace est::loop

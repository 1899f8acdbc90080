#pragma once
// Pending inputs in timestamp order, statically sized, ETL style: InputQueue is the runtime-capacity interface the
// loop takes, InputQueueStorage<Capacity, KMax, ScanSlots> owns the arrays (Capacity inputs, of which at most
// ScanSlots scans of at most KMax readings). Ties in time are ordered by kind (the order of est/loop/input_kinds.hpp),
// the features of one landmark sighting by their content (id, range, bearing, signature), and then by arrival, so the
// same inputs give the same order whatever order they arrived in within the reorder window (an EKF's result depends
// on the order features are fused in). Every operation is bounded by the capacity.
#include <cstdint>

#include "est/loop/input_kinds.hpp"
#include "est/loop/inputs.hpp"

namespace est::loop {

struct QueuedInput {
  union Payload {
    Payload() : ticks() {}
    WheelTicksInput ticks;
    SteeringInput steering;
    TwistInput twist;
    OdometryInput odometry;
    LandmarkInput landmark;
    std::uint8_t scan_slot;  // kind == scan: index into the scan slots
  };
  InputKind kind = InputKind::wheel_ticks;
  TimeNs t_ns = 0;
  std::uint32_t arrival = 0;  // tie-break among equal (t, kind)
  Payload p;
};

class InputQueue {
 public:
  InputQueue(const InputQueue&) = delete;
  InputQueue& operator=(const InputQueue&) = delete;

  std::uint32_t capacity() const { return capacity_; }
  std::int32_t max_beams() const { return max_beams_; }
  std::uint32_t size() const { return count_; }
  bool empty() const { return count_ == 0u; }
  const QueuedInput& front() const { return items_[0]; }
  TimeNs front_time() const { return items_[0].t_ns; }

  // False when the queue is full.
  template <typename Payload>
  bool push(const Payload& in) {
    QueuedInput q;
    q.kind = KindOf<Payload>::value;
    q.t_ns = in.t_ns;
    set(q.p, in);
    return insert(q);
  }
  // Copies the readings. False when the queue or the scan slots are full, or the scan has more than KMax readings.
  bool push(const ScanInput& in) {
    if (in.layout.count <= 0 || in.layout.count > max_beams_ || in.ranges == nullptr || count_ == capacity_)
      return false;
    std::uint32_t slot = 0;
    while (slot < slot_count_ && slots_[slot].used) ++slot;
    if (slot == slot_count_) return false;
    slots_[slot].layout = in.layout;
    float* r = ranges_of(slot);
    for (std::int32_t k = 0; k < in.layout.count; ++k) r[k] = in.ranges[k];
    QueuedInput q;
    q.kind = InputKind::scan;
    q.t_ns = in.t_ns;
    q.p.scan_slot = static_cast<std::uint8_t>(slot);
    if (!insert(q)) return false;
    slots_[slot].used = true;
    return true;
  }

  // The scan of a queued scan input, valid until pop() releases it.
  ScanInput scan(const QueuedInput& q) const {
    return {q.t_ns, slots_[q.p.scan_slot].layout, ranges_of(q.p.scan_slot)};
  }

  // The first queued input of `kind` after the front one (queue order), or null: the loop borrows part of the next
  // increment to bring the motion up to a correction's time.
  QueuedInput* next_of_kind(InputKind kind) {
    for (std::uint32_t i = 1; i < count_; ++i)
      if (items_[i].kind == kind) return &items_[i];
    return nullptr;
  }

  void pop() {
    if (count_ == 0u) return;
    if (items_[0].kind == InputKind::scan) slots_[items_[0].p.scan_slot].used = false;
    for (std::uint32_t i = 1; i < count_; ++i) items_[i - 1] = items_[i];
    --count_;
  }

 protected:
  struct ScanSlot {
    ScanLayout layout;
    bool used = false;
  };
  InputQueue(QueuedInput* items, std::uint32_t capacity, ScanSlot* slots, std::uint32_t slot_count, float* ranges,
             std::int32_t max_beams)
      : items_(items), slots_(slots), ranges_(ranges), capacity_(capacity), slot_count_(slot_count),
        max_beams_(max_beams) {}
  ~InputQueue() = default;

 private:
  static void set(QueuedInput::Payload& p, const WheelTicksInput& in) { p.ticks = in; }
  static void set(QueuedInput::Payload& p, const SteeringInput& in) { p.steering = in; }
  static void set(QueuedInput::Payload& p, const TwistInput& in) { p.twist = in; }
  static void set(QueuedInput::Payload& p, const OdometryInput& in) { p.odometry = in; }
  static void set(QueuedInput::Payload& p, const LandmarkInput& in) { p.landmark = in; }

  float* ranges_of(std::uint32_t slot) const {
    return ranges_ + static_cast<std::uint32_t>(max_beams_) * slot;
  }

  static bool before(const QueuedInput& a, const QueuedInput& b) {
    if (a.t_ns != b.t_ns) return a.t_ns < b.t_ns;
    if (a.kind != b.kind) return a.kind < b.kind;
    if (a.kind == InputKind::landmark) {
      const LandmarkInput& x = a.p.landmark;
      const LandmarkInput& y = b.p.landmark;
      if (x.id != y.id) return x.id < y.id;
      if (x.range_m != y.range_m) return x.range_m < y.range_m;  // a NaN one stays where it arrived (it is rejected)
      if (x.bearing_rad != y.bearing_rad) return x.bearing_rad < y.bearing_rad;
      if (x.signature != y.signature) return x.signature < y.signature;
    }
    return a.arrival < b.arrival;
  }

  bool insert(QueuedInput q) {
    if (count_ == capacity_) return false;
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

  QueuedInput* items_;
  ScanSlot* slots_;
  float* ranges_;
  std::uint32_t capacity_;
  std::uint32_t slot_count_;
  std::int32_t max_beams_;
  std::uint32_t count_ = 0;
  std::uint32_t arrivals_ = 0;
};

template <std::uint32_t Capacity, std::int32_t KMax, std::uint32_t ScanSlots>
class InputQueueStorage final : public InputQueue {
  static_assert(Capacity >= 2u && ScanSlots >= 1u && ScanSlots <= 255u && KMax > 0, "bad queue capacities");

 public:
  InputQueueStorage() : InputQueue(items_, Capacity, slots_, ScanSlots, ranges_, KMax) {}

 private:
  QueuedInput items_[Capacity];
  ScanSlot slots_[ScanSlots];
  float ranges_[static_cast<std::uint32_t>(KMax) * ScanSlots] = {};
};

}  // namespace est::loop

#pragma once
// A bounded queue of raw LCM messages (channel, payload bytes, receive time) between the thread that drains an LCM
// socket and the node's loop (node/lcm_receiver.hpp). Fixed capacity, allocated and touched once at construction:
// its memory never grows. When full it drops the OLDEST message: a live input that waited longest is the one the
// gate is closest to rejecting as stale (100-200 ms of stream time, 2-4 ms of wall time at 50x), while the newest
// is what the filter wants next; dropping the newest would keep the loop working on a backlog that ages as it goes.
// Every drop is counted by channel, and why (the queue was full, or the payload larger than a slot, which no valid
// input is). Thread-safe: one producer, one consumer (a mutex; pushes and pops only move a slot index).
// Host only.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

namespace node {

inline constexpr std::size_t kRawQueueMaxChannels = 16;

struct RawMessage {
  std::uint8_t channel = 0;  // index into the receiver's channel list
  std::int64_t receive_ns = 0;
  std::size_t size = 0;
  std::vector<std::uint8_t> bytes;  // slot_bytes long; size of them used
};

struct RawQueueCounters {
  std::uint64_t received[kRawQueueMaxChannels] = {};
  std::uint64_t handed[kRawQueueMaxChannels] = {};
  std::uint64_t dropped_full[kRawQueueMaxChannels] = {};
  std::uint64_t dropped_oversize[kRawQueueMaxChannels] = {};
  std::size_t high_water = 0;
  std::size_t queued = 0;

  static std::uint64_t sum(const std::uint64_t (&v)[kRawQueueMaxChannels]) {
    std::uint64_t s = 0;
    for (std::uint64_t x : v) s += x;
    return s;
  }
};

class RawMessageQueue {
 public:
  RawMessageQueue(std::size_t capacity, std::size_t slot_bytes) : slots_(capacity), slot_bytes_(slot_bytes) {
    for (RawMessage& m : slots_) m.bytes.assign(slot_bytes, 0);  // touched now: the resident memory is flat from here
  }

  std::size_t capacity() const { return slots_.size(); }
  std::size_t slot_bytes() const { return slot_bytes_; }

  // Producer: copies the message in; drops the oldest when full (or this one when it does not fit a slot).
  void push(std::uint8_t channel, const void* data, std::size_t size, std::int64_t receive_ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++c_.received[channel];
    if (size > slot_bytes_) {
      ++c_.dropped_oversize[channel];
      return;
    }
    if (count_ == capacity()) {
      ++c_.dropped_full[slots_[head_].channel];
      head_ = next(head_);
      --count_;
    }
    RawMessage& m = slots_[tail_];
    m.channel = channel;
    m.receive_ns = receive_ns;
    m.size = size;
    std::memcpy(m.bytes.data(), data, size);
    tail_ = next(tail_);
    ++count_;
    if (count_ > c_.high_water) c_.high_water = count_;
  }

  // Consumer: the oldest message into `out` (whose buffer it swaps with the slot's: no copy, no allocation);
  // false when empty.
  bool pop(RawMessage& out) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (count_ == 0) return false;
    RawMessage& m = slots_[head_];
    if (out.bytes.size() != slot_bytes_) out.bytes.assign(slot_bytes_, 0);
    out.channel = m.channel;
    out.receive_ns = m.receive_ns;
    out.size = m.size;
    out.bytes.swap(m.bytes);
    ++c_.handed[m.channel];
    head_ = next(head_);
    --count_;
    return true;
  }

  RawQueueCounters counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    RawQueueCounters c = c_;
    c.queued = count_;
    return c;
  }

 private:
  std::size_t next(std::size_t i) const { return i + 1 == slots_.size() ? 0 : i + 1; }

  mutable std::mutex mutex_;
  std::vector<RawMessage> slots_;
  std::size_t slot_bytes_;
  std::size_t head_ = 0, tail_ = 0, count_ = 0;
  RawQueueCounters c_;
};

}  // namespace node

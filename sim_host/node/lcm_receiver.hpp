#pragma once
// Live LCM input drained by a thread of its own (issue 14, "Load"): the thread owns the udpm LCM instance and calls
// lcm_handle_timeout in a loop, as fast as the kernel delivers, copying each message of the given channels into a
// bounded queue (node/raw_message_queue.hpp: fixed capacity, drop-oldest, every drop counted by channel). The node's
// loop takes them from the queue when it can and feeds them through its usual input path. So a loop that falls
// behind loses inputs where they are counted, in the queue, instead of inside LCM's own receive buffers (which
// LCM 1.3 fills and empties silently when its handler does not run) or the kernel's socket buffer.
// wake_fd() becomes readable when a message is queued (an eventfd the loop polls beside its other inputs). Host only.
#include <atomic>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "node/raw_message_queue.hpp"

namespace node {

// 256 messages: at 10x the 60 s office stream (1600 messages/s) that is 160 ms of wall time, several MCL steps of
// 20000 particles; 8 KiB slots: the largest valid input is a range scan of the node's 1440 beams (5.8 KB).
inline constexpr std::size_t kLcmQueueCapacity = 256;
inline constexpr std::size_t kLcmQueueSlotBytes = 8192;

class LcmReceiver {
 public:
  // Opens `url` (good() says whether it could) and subscribes `channels` (at most kRawQueueMaxChannels); the thread
  // starts with start().
  LcmReceiver(const std::string& url, std::vector<std::string> channels, std::size_t capacity = kLcmQueueCapacity,
              std::size_t slot_bytes = kLcmQueueSlotBytes);
  ~LcmReceiver();
  LcmReceiver(const LcmReceiver&) = delete;
  LcmReceiver& operator=(const LcmReceiver&) = delete;

  bool good() const { return good_; }
  void start();
  // Stops the thread (the messages already queued stay for pop()).
  void stop();

  int wake_fd() const { return wake_fd_; }
  // Clears the wake-up (call before draining with pop()).
  void clear_wake();
  bool pop(RawMessage& out) { return queue_.pop(out); }

  const std::vector<std::string>& channels() const { return channels_; }
  RawQueueCounters counters() const { return queue_.counters(); }
  std::size_t capacity() const { return queue_.capacity(); }
  std::size_t slot_bytes() const { return queue_.slot_bytes(); }
  std::uint64_t handle_errors() const { return handle_errors_.load(); }

 private:
  struct Handler;
  void run();

  std::vector<std::string> channels_;
  RawMessageQueue queue_;
  std::unique_ptr<::lcm::LCM> lcm_;
  std::vector<std::unique_ptr<Handler>> handlers_;
  bool good_ = false;
  int wake_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> handle_errors_{0};
  std::thread thread_;
};

}  // namespace node

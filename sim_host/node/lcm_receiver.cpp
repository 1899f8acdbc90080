// Live LCM input drained by a thread of its own (node/lcm_receiver.hpp).
#include "node/lcm_receiver.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>

#include "hal/socketcan/socketcan_bus.hpp"

namespace node {

struct LcmReceiver::Handler {
  LcmReceiver* owner;
  std::uint8_t channel;
  void on(const ::lcm::ReceiveBuffer* rbuf, const std::string&) {
    owner->queue_.push(channel, rbuf->data, rbuf->data_size, hal::socketcan::monotonic_now_ns());
    const std::uint64_t one = 1;
    (void)!::write(owner->wake_fd_, &one, sizeof one);
  }
};

LcmReceiver::LcmReceiver(const std::string& url, std::vector<std::string> channels, std::size_t capacity,
                         std::size_t slot_bytes)
    : channels_(std::move(channels)), queue_(capacity, slot_bytes) {
  if (channels_.size() > kRawQueueMaxChannels) throw std::invalid_argument("LcmReceiver: too many channels");
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  lcm_ = std::make_unique<::lcm::LCM>(url);
  good_ = wake_fd_ >= 0 && lcm_->good();
  if (!good_) return;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    handlers_.push_back(std::make_unique<Handler>(Handler{this, static_cast<std::uint8_t>(i)}));
    ::lcm::Subscription* s = lcm_->subscribe(channels_[i], &Handler::on, handlers_.back().get());
    // LCM's own per-subscription queue (30 messages by default) fills only while this thread is not in handle:
    // room for a scheduling hiccup of the thread at 50x.
    if (s != nullptr) s->setQueueCapacity(1000);
  }
}

LcmReceiver::~LcmReceiver() {
  stop();
  if (wake_fd_ >= 0) ::close(wake_fd_);
}

void LcmReceiver::start() {
  if (good_ && !thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void LcmReceiver::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void LcmReceiver::clear_wake() {
  std::uint64_t n = 0;
  (void)!::read(wake_fd_, &n, sizeof n);
}

void LcmReceiver::run() {
  // 20 ms: how long a stop waits at most.
  while (!stop_.load(std::memory_order_relaxed))
    if (lcm_->handleTimeout(20) < 0) {
      handle_errors_.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a failing socket must not spin a core
    }
}

}  // namespace node

#pragma once
// SocketCAN backend (Linux): one raw CAN socket, non-blocking, with kernel receive filters for the estimator's ids,
// kernel receive timestamps, controller error frames folded into a status word, and reconnection when the
// interface goes down or disappears and comes back. Host only.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/can/frame.hpp"
#include "hal/time.hpp"

namespace hal::socketcan {

struct RxFrame {
  can::CanFrame frame;
  TimeNs stamp_ns = 0;          // kernel receive time, on CLOCK_MONOTONIC (see SocketCanBus::receive)
  TimeNs kernel_realtime_ns = 0;  // the kernel's SO_TIMESTAMPNS stamp as given (CLOCK_REALTIME)
};

struct Config {
  std::string interface = "vcan0";
  std::vector<std::uint32_t> receive_ids;     // kernel filter: only these standard ids; empty = every data frame
  TimeNs reconnect_interval_ns = 100 * kNsPerMs;
  bool receive_error_frames = true;
  bool receive_own_frames = false;             // CAN_RAW_RECV_OWN_MSGS
  // The socket's receive queue, bytes (0: the kernel's default, rmem_default, ~200 frames): SO_RCVBUFFORCE where
  // permitted (CAP_NET_ADMIN), else SO_RCVBUF (capped by net.core.rmem_max). A frame takes ~1 KB of it.
  int receive_buffer_bytes = 0;
};

struct Counters {
  std::uint64_t rx_frames = 0;
  std::uint64_t tx_frames = 0;
  std::uint64_t tx_failed = 0;       // queue full (EAGAIN/ENOBUFS) or link down
  std::uint64_t rx_dropped = 0;      // frames the kernel dropped for us (SO_RXQ_OVFL)
  std::uint64_t error_frames = 0;
  std::uint64_t bus_off_events = 0;
  std::uint64_t link_lost = 0;       // the interface went down or disappeared
  std::uint64_t reconnects = 0;      // and came back
  std::uint64_t rx_ignored = 0;      // remote, extended-id or CAN FD frames (not part of the interface)
};

class SocketCanBus final : public can::CanTx {
 public:
  explicit SocketCanBus(Config config);
  ~SocketCanBus();
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  // Opens and binds the socket. false (with errno-style reason in last_error()) when the interface is missing,
  // down or the kernel has no CAN; service() keeps retrying.
  bool open();
  void close();
  bool is_open() const { return fd_ >= 0; }

  // Reads what is queued, at most max frames, without blocking. Error frames update status() and are not returned.
  std::size_t receive(RxFrame* out, std::size_t max);
  // Non-blocking send; false when the kernel queue is full or the link is down (counted).
  bool send(const can::CanFrame& frame) override;

  // Watches the link (interface flags) and reopens when it is back, every reconnect_interval_ns at most.
  void service(TimeNs now_ns);

  // hal::status::kCan* bits. Link down, bus-off, error-passive and error-warning are states (cleared when the
  // controller reports recovery or the link is back); overflow, tx failure and protocol errors are events, kept
  // until take_status() hands them to the loop.
  std::uint32_t status() const { return status_; }
  std::uint32_t take_status();
  const Counters& counters() const { return counters_; }
  const std::string& last_error() const { return last_error_; }
  int fd() const { return fd_; }  // for poll()/epoll in a node's event loop; -1 when closed

 private:
  void link_lost(const std::string& why);
  bool fail(const std::string& why);
  void on_error_frame(std::uint32_t can_id, const std::uint8_t* data);
  bool link_up() const;

  Config config_;
  int fd_ = -1;
  int ifindex_ = 0;
  std::uint32_t status_ = 0;
  Counters counters_;
  TimeNs next_retry_ns_ = 0;
  bool was_open_ = false;
  std::uint32_t last_rxq_ovfl_ = 0;
  std::string last_error_;
};

// CLOCK_MONOTONIC now, for the host's Clock port.
TimeNs monotonic_now_ns();

}  // namespace hal::socketcan

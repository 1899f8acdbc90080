// SocketCAN backend (hal/socketcan/socketcan_bus.hpp).
#include "hal/socketcan/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "hal/status_word.hpp"

namespace hal::socketcan {

namespace {

TimeNs clock_ns(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<TimeNs>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

constexpr std::uint32_t kEventBits = status::kCanRxOverflow | status::kCanTxFailed | status::kCanProtocolError;

bool is_link_errno(int e) { return e == ENETDOWN || e == ENODEV || e == ENXIO || e == ENETUNREACH; }

}  // namespace

TimeNs monotonic_now_ns() { return clock_ns(CLOCK_MONOTONIC); }

SocketCanBus::SocketCanBus(Config config) : config_(std::move(config)) { status_ = status::kCanLinkDown; }

SocketCanBus::~SocketCanBus() { close(); }

void SocketCanBus::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SocketCanBus::fail(const std::string& why) {
  last_error_ = why;
  close();
  status_ |= status::kCanLinkDown;
  return false;
}

bool SocketCanBus::open() {
  close();
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) return fail(std::string("socket(PF_CAN): ") + std::strerror(errno));

  ifreq ifr{};
  std::strncpy(ifr.ifr_name, config_.interface.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) return fail(config_.interface + ": " + std::strerror(errno));
  ifindex_ = ifr.ifr_ifindex;
  if (::ioctl(fd_, SIOCGIFFLAGS, &ifr) < 0 || (ifr.ifr_flags & IFF_UP) == 0)
    return fail(config_.interface + ": interface is down");

  if (!config_.receive_ids.empty()) {
    std::vector<can_filter> filters;
    for (std::uint32_t id : config_.receive_ids)
      filters.push_back({id & CAN_SFF_MASK, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG});
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(),
                     static_cast<socklen_t>(filters.size() * sizeof(can_filter))) < 0)
      return fail(std::string("CAN_RAW_FILTER: ") + std::strerror(errno));
  }
  const can_err_mask_t err_mask = config_.receive_error_frames ? CAN_ERR_MASK : 0u;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) < 0)
    return fail(std::string("CAN_RAW_ERR_FILTER: ") + std::strerror(errno));
  const int own = config_.receive_own_frames ? 1 : 0;
  const int on = 1;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &own, sizeof own) < 0 ||
      ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0 ||
      ::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) < 0)
    return fail(std::string("setsockopt: ") + std::strerror(errno));
  if (config_.receive_buffer_bytes > 0 &&
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &config_.receive_buffer_bytes, sizeof(int)) < 0 &&
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &config_.receive_buffer_bytes, sizeof(int)) < 0)
    return fail(std::string("SO_RCVBUF: ") + std::strerror(errno));

  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifindex_;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0)
    return fail(std::string("bind: ") + std::strerror(errno));

  // A fresh controller state: the kernel reports bus-off and error-passive again if they persist.
  status_ &= ~(status::kCanLinkDown | status::kCanBusOff | status::kCanErrorPassive | status::kCanErrorWarning);
  last_rxq_ovfl_ = 0;
  last_error_.clear();
  if (was_open_) ++counters_.reconnects;
  was_open_ = true;
  return true;
}

void SocketCanBus::link_lost(const std::string& why) {
  ++counters_.link_lost;
  fail(why);
}

bool SocketCanBus::link_up() const {
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, config_.interface.c_str(), IFNAMSIZ - 1);
  // A deleted and re-added interface has a new index: the old binding is dead even though the name is back.
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0 || ifr.ifr_ifindex != ifindex_) return false;
  if (::ioctl(fd_, SIOCGIFFLAGS, &ifr) < 0) return false;
  return (ifr.ifr_flags & IFF_UP) != 0;
}

void SocketCanBus::service(TimeNs now_ns) {
  if (fd_ >= 0) {
    if (!link_up()) link_lost(config_.interface + ": interface down or gone");
    return;
  }
  if (now_ns < next_retry_ns_) return;
  next_retry_ns_ = now_ns + config_.reconnect_interval_ns;
  open();
}

std::uint32_t SocketCanBus::take_status() {
  const std::uint32_t s = status_;
  status_ &= ~kEventBits;
  return s;
}

void SocketCanBus::on_error_frame(std::uint32_t can_id, const std::uint8_t* data) {
  ++counters_.error_frames;
  if (can_id & CAN_ERR_BUSOFF) {
    if ((status_ & status::kCanBusOff) == 0) ++counters_.bus_off_events;
    status_ |= status::kCanBusOff;
  }
  if (can_id & CAN_ERR_RESTARTED)
    status_ &= ~(status::kCanBusOff | status::kCanErrorPassive | status::kCanErrorWarning);
  if (can_id & CAN_ERR_CRTL) {
    const std::uint8_t c = data[1];
    if (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) status_ |= status::kCanErrorPassive;
    if (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) status_ |= status::kCanErrorWarning;
    if (c & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) status_ |= status::kCanRxOverflow;
#ifdef CAN_ERR_CRTL_ACTIVE
    if (c & CAN_ERR_CRTL_ACTIVE) status_ &= ~(status::kCanErrorPassive | status::kCanErrorWarning);
#endif
  }
  if (can_id & (CAN_ERR_PROT | CAN_ERR_ACK | CAN_ERR_LOSTARB | CAN_ERR_BUSERROR | CAN_ERR_TX_TIMEOUT | CAN_ERR_TRX))
    status_ |= status::kCanProtocolError;
}

std::size_t SocketCanBus::receive(RxFrame* out, std::size_t max) {
  if (fd_ < 0) return 0;
  // Kernel stamps are CLOCK_REALTIME; the offset to CLOCK_MONOTONIC is taken once per call, between two
  // monotonic readings, so a wall-clock step can only shift the stamps of frames queued before it.
  const TimeNs mono_before = clock_ns(CLOCK_MONOTONIC);
  const TimeNs real = clock_ns(CLOCK_REALTIME);
  const TimeNs mono_after = clock_ns(CLOCK_MONOTONIC);
  const TimeNs real_minus_mono = real - (mono_before + (mono_after - mono_before) / 2);

  std::size_t n = 0;
  // Bounded: at most max frames, plus as many error/ignored frames as the queue holds at most (kernel rcvbuf).
  for (std::size_t reads = 0; n < max && reads < max + 1024u; ++reads) {
    can_frame cf{};
    iovec iov{&cf, sizeof cf};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t r = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (r < 0) {
      if (errno == EINTR) continue;
      if (is_link_errno(errno)) link_lost(config_.interface + ": " + std::strerror(errno));
      break;
    }
    if (static_cast<std::size_t>(r) != sizeof cf) {
      ++counters_.rx_ignored;
      continue;
    }
    TimeNs kernel_ns = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        kernel_ns = static_cast<TimeNs>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t dropped = 0;
        std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
        if (dropped != last_rxq_ovfl_) {
          counters_.rx_dropped += static_cast<std::uint32_t>(dropped - last_rxq_ovfl_);
          last_rxq_ovfl_ = dropped;
          status_ |= status::kCanRxOverflow;
        }
      }
    }
    if (cf.can_id & CAN_ERR_FLAG) {
      on_error_frame(cf.can_id, cf.data);
      continue;
    }
    if ((cf.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG)) != 0 || cf.can_dlc > can::kMaxDlc) {
      ++counters_.rx_ignored;
      continue;
    }
    RxFrame& f = out[n++];
    f.frame.id = cf.can_id & CAN_SFF_MASK;
    f.frame.dlc = cf.can_dlc;
    std::memset(f.frame.data, 0, sizeof f.frame.data);
    std::memcpy(f.frame.data, cf.data, cf.can_dlc);
    f.kernel_realtime_ns = kernel_ns;
    f.stamp_ns = kernel_ns != 0 ? kernel_ns - real_minus_mono : mono_after;
    if (f.stamp_ns > mono_after) f.stamp_ns = mono_after;
    ++counters_.rx_frames;
  }
  return n;
}

bool SocketCanBus::send(const can::CanFrame& frame) {
  if (fd_ < 0 || frame.dlc > can::kMaxDlc) {
    ++counters_.tx_failed;
    status_ |= status::kCanTxFailed;
    return false;
  }
  can_frame cf{};
  cf.can_id = frame.id & CAN_SFF_MASK;
  cf.can_dlc = frame.dlc;
  std::memcpy(cf.data, frame.data, frame.dlc);
  const ssize_t w = ::write(fd_, &cf, sizeof cf);
  if (w == static_cast<ssize_t>(sizeof cf)) {
    ++counters_.tx_frames;
    return true;
  }
  const int e = errno;
  ++counters_.tx_failed;
  status_ |= status::kCanTxFailed;
  if (w < 0 && is_link_errno(e)) link_lost(config_.interface + ": " + std::strerror(e));
  return false;
}

}  // namespace hal::socketcan

#pragma once
// A classic CAN data frame as the codec sees it (11-bit ids; the interface has no extended ids and no RTR).
#include <cstdint>

namespace hal::can {

inline constexpr std::uint8_t kMaxDlc = 8;

struct CanFrame {
  std::uint32_t id = 0;
  std::uint8_t dlc = 0;
  std::uint8_t data[kMaxDlc] = {};
};

// Where encoded frames go: a SocketCAN socket on the host, a controller's mailbox on the board.
class CanTx {
 public:
  // false when the frame could not be queued (the caller counts it).
  virtual bool send(const CanFrame& frame) = 0;

 protected:
  ~CanTx() = default;
};

}  // namespace hal::can

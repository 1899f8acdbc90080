#pragma once
// One CAN frame as a line of a candump log (can-utils `candump -l`, replayed by `canplayer`):
//   (1436509052.249713) vcan0 100#0102030405060708
// seconds.microseconds of the receive time, the interface, the id in hex and the data bytes in hex. Pure text
// handling, no I/O: the host and the board image (over semihosting) read and write the same lines. Stamps are
// nanoseconds of the monotonic clock the log was taken with, to the microsecond the format keeps.
#include <cstddef>
#include <cstdint>

#include "hal/can/frame.hpp"
#include "hal/time.hpp"

namespace hal::can {

enum class CandumpStatus : std::uint8_t { ok, blank, bad_stamp, bad_interface, bad_id, bad_data };
const char* to_string(CandumpStatus s);

// Parses one line (without its newline; a trailing '\r' is ignored). Blank lines and '#' comments are `blank`.
CandumpStatus parse_candump_line(const char* line, std::size_t length, CanFrame& frame, TimeNs& stamp_ns);

// Writes one line and a newline into out (at least kCandumpLineMax bytes); returns the length written. The
// interface name is cut to 15 characters.
inline constexpr std::size_t kCandumpLineMax = 64;
std::size_t format_candump_line(const CanFrame& frame, TimeNs stamp_ns, const char* interface, char* out);

}  // namespace hal::can

// candump log lines (hal/can/candump.hpp).
#include "hal/can/candump.hpp"

namespace hal::can {

namespace {
int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

const char* to_string(CandumpStatus s) {
  switch (s) {
    case CandumpStatus::ok: return "ok";
    case CandumpStatus::blank: return "blank";
    case CandumpStatus::bad_stamp: return "bad_stamp";
    case CandumpStatus::bad_interface: return "bad_interface";
    case CandumpStatus::bad_id: return "bad_id";
    case CandumpStatus::bad_data: return "bad_data";
  }
  return "unknown";
}

CandumpStatus parse_candump_line(const char* line, std::size_t n, CanFrame& frame, TimeNs& stamp_ns) {
  while (n > 0 && (line[n - 1] == '\r' || line[n - 1] == ' ')) --n;
  std::size_t i = 0;
  while (i < n && line[i] == ' ') ++i;
  if (i == n || line[i] == '#') return CandumpStatus::blank;
  // (seconds.microseconds)
  if (line[i++] != '(') return CandumpStatus::bad_stamp;
  std::int64_t sec = 0, usec = 0;
  int digits = 0;
  while (i < n && line[i] >= '0' && line[i] <= '9' && digits < 12) {
    sec = sec * 10 + (line[i++] - '0');
    ++digits;
  }
  if (digits == 0 || i >= n || line[i++] != '.') return CandumpStatus::bad_stamp;
  digits = 0;
  while (i < n && line[i] >= '0' && line[i] <= '9') {
    if (digits < 9) usec = usec * 10 + (line[i] - '0');
    ++digits;
    ++i;
  }
  if (digits != 6 || i >= n || line[i++] != ')') return CandumpStatus::bad_stamp;
  if (sec > (INT64_MAX - (kNsPerS - 1)) / kNsPerS) return CandumpStatus::bad_stamp;  // beyond int64 nanoseconds
  stamp_ns = sec * kNsPerS + usec * 1000;
  // interface
  if (i >= n || line[i++] != ' ') return CandumpStatus::bad_interface;
  std::size_t name = 0;
  while (i < n && line[i] != ' ') {
    ++i;
    ++name;
  }
  if (name == 0 || name > 15 || i >= n) return CandumpStatus::bad_interface;
  ++i;
  // id#data: an 11-bit id in three hex digits (extended ids, RTR and CAN FD frames are not of this bus)
  std::uint32_t id = 0;
  digits = 0;
  while (i < n && line[i] != '#') {
    const int d = hex_digit(line[i++]);
    if (d < 0 || digits >= 3) return CandumpStatus::bad_id;
    id = (id << 4) | static_cast<std::uint32_t>(d);
    ++digits;
  }
  if (digits != 3 || id > 0x7FFu || i >= n) return CandumpStatus::bad_id;
  ++i;
  CanFrame f;
  f.id = id;
  std::uint8_t len = 0;
  while (i < n) {
    if (i + 1 >= n || len >= kMaxDlc) return CandumpStatus::bad_data;
    const int hi = hex_digit(line[i]), lo = hex_digit(line[i + 1]);
    if (hi < 0 || lo < 0) return CandumpStatus::bad_data;
    f.data[len++] = static_cast<std::uint8_t>((hi << 4) | lo);
    i += 2;
  }
  f.dlc = len;
  frame = f;
  return CandumpStatus::ok;
}

std::size_t format_candump_line(const CanFrame& frame, TimeNs stamp_ns, const char* interface, char* out) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::size_t n = 0;
  const TimeNs t = stamp_ns < 0 ? 0 : stamp_ns;
  std::int64_t sec = t / kNsPerS;
  const std::int64_t usec = (t % kNsPerS) / 1000;
  char digits[20];
  int d = 0;
  do {
    digits[d++] = static_cast<char>('0' + sec % 10);
    sec /= 10;
  } while (sec > 0 && d < 19);
  out[n++] = '(';
  while (d > 0) out[n++] = digits[--d];
  out[n++] = '.';
  std::int64_t div = 100000;
  for (int k = 0; k < 6; ++k, div /= 10) out[n++] = static_cast<char>('0' + (usec / div) % 10);
  out[n++] = ')';
  out[n++] = ' ';
  for (int k = 0; k < 15 && interface[k] != '\0'; ++k) out[n++] = interface[k];
  out[n++] = ' ';
  out[n++] = kHex[(frame.id >> 8) & 0x7u];
  out[n++] = kHex[(frame.id >> 4) & 0xFu];
  out[n++] = kHex[frame.id & 0xFu];
  out[n++] = '#';
  const std::uint8_t len = frame.dlc > kMaxDlc ? kMaxDlc : frame.dlc;
  for (std::uint8_t k = 0; k < len; ++k) {
    out[n++] = kHex[frame.data[k] >> 4];
    out[n++] = kHex[frame.data[k] & 0xFu];
  }
  out[n++] = '\n';
  return n;
}

}  // namespace hal::can

#pragma once
// What every message codec of estimator.dbc shares: the status of an encode or decode, a writer that packs signals
// by their table and keeps the first failure, and the frame checks (id, DLC, the per-frame CRC-8).
#include <cstdint>

#include "hal/can/crc.hpp"
#include "hal/can/frame.hpp"
#include "hal/can/signal.hpp"
#include "hal/can/signal_spec.hpp"

namespace hal::can {

enum class CodecStatus : std::uint8_t {
  ok,
  wrong_id,      // the frame is another message
  wrong_dlc,     // not the DBC's length
  bad_checksum,  // per-frame CRC-8 mismatch
  not_finite,    // encode: NaN or infinity in a signal that has no code for it
  out_of_range,  // encode: outside the signal's DBC range
};

const char* to_string(CodecStatus s);

class FrameWriter {
 public:
  FrameWriter(CanFrame& f, std::uint32_t id, const SignalSpec* signals) : f_(f), signals_(signals) {
    f_ = CanFrame{};
    f_.id = id;
    f_.dlc = 8;
  }
  void physical(std::size_t i, float v) { note(encode_physical(f_.data, signals_[i], v)); }
  void integer(std::size_t i, std::int64_t v) { note(encode_integer(f_.data, signals_[i], v)); }
  // The CRC-8 of the frame so far into signal i (the checksum, last).
  void checksum(std::size_t i) { integer(i, frame_crc8(f_.id, f_.data)); }
  CodecStatus status() const { return status_; }

 private:
  void note(EncodeStatus e) {
    if (status_ != CodecStatus::ok) return;
    if (e == EncodeStatus::not_finite) status_ = CodecStatus::not_finite;
    if (e == EncodeStatus::out_of_range) status_ = CodecStatus::out_of_range;
  }
  CanFrame& f_;
  const SignalSpec* signals_;
  CodecStatus status_ = CodecStatus::ok;
};

inline CodecStatus check_frame(const CanFrame& f, std::uint32_t id) {
  if (f.id != id) return CodecStatus::wrong_id;
  if (f.dlc != 8) return CodecStatus::wrong_dlc;
  return CodecStatus::ok;
}
// check_frame and the CRC-8 in signal `checksum`.
inline CodecStatus check_frame(const CanFrame& f, std::uint32_t id, const SignalSpec& checksum) {
  const CodecStatus c = check_frame(f, id);
  if (c != CodecStatus::ok) return c;
  if (static_cast<std::uint8_t>(extract_raw(f.data, checksum)) != frame_crc8(f.id, f.data))
    return CodecStatus::bad_checksum;
  return CodecStatus::ok;
}

inline std::uint8_t raw_u8(const CanFrame& f, const SignalSpec& s) {
  return static_cast<std::uint8_t>(extract_raw(f.data, s));
}
inline std::uint16_t raw_u16(const CanFrame& f, const SignalSpec& s) {
  return static_cast<std::uint16_t>(extract_raw(f.data, s));
}
inline std::int64_t counter4(std::uint8_t c) { return c & 0x0F; }

}  // namespace hal::can

#pragma once
// The two checksums of the interface (estimator.dbc): CRC-8 SAE J1850 per frame, CRC-16/CCITT-FALSE per scan.
// Bitwise (no tables): a frame is at most 10 bytes, and flash matters more than cycles here.
#include <cstddef>
#include <cstdint>

namespace hal::can {

// CRC-8 SAE J1850: poly 0x1D, init 0xFF, xorout 0xFF (AUTOSAR Crc_CalculateCRC8); check("123456789") = 0x4B.
class Crc8J1850 {
 public:
  constexpr void add(std::uint8_t byte) {
    unsigned c = static_cast<unsigned>(crc_) ^ static_cast<unsigned>(byte);
    for (int b = 0; b < 8; ++b) c = (c & 0x80u) ? (c << 1) ^ 0x1Du : (c << 1);
    crc_ = static_cast<std::uint8_t>(c & 0xFFu);
  }
  constexpr void add(const std::uint8_t* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) add(p[i]);
  }
  constexpr std::uint8_t value() const { return static_cast<std::uint8_t>(crc_ ^ 0xFFu); }

 private:
  std::uint8_t crc_ = 0xFF;
};

// CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no xorout; check("123456789") = 0x29B1.
class Crc16Ccitt {
 public:
  constexpr void add(std::uint8_t byte) {
    unsigned c = static_cast<unsigned>(crc_) ^ (static_cast<unsigned>(byte) << 8);
    for (int b = 0; b < 8; ++b) c = (c & 0x8000u) ? (c << 1) ^ 0x1021u : (c << 1);
    crc_ = static_cast<std::uint16_t>(c & 0xFFFFu);
  }
  constexpr void add(const std::uint8_t* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) add(p[i]);
  }
  constexpr std::uint16_t value() const { return crc_; }

 private:
  std::uint16_t crc_ = 0xFFFF;
};

// The per-frame checksum of estimator.dbc: the id (low byte, high byte) then bytes 0-6; it sits in byte 7.
constexpr std::uint8_t frame_crc8(std::uint32_t id, const std::uint8_t* data) {
  Crc8J1850 c;
  c.add(static_cast<std::uint8_t>(id & 0xFFu));
  c.add(static_cast<std::uint8_t>((id >> 8) & 0xFFu));
  c.add(data, 7);
  return c.value();
}

}  // namespace hal::can

#pragma once
// FNV-1a 64-bit digest over the exact bit patterns of results: equal digests mean bit-identical outputs.
#include <cstdint>
#include <cstring>

namespace est {

class Digest {
 public:
  constexpr void add_u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
      h_ ^= (v >> (8 * i)) & 0xffu;
      h_ *= 0x100000001b3ull;
    }
  }
  void add(float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    add_u32(bits);
  }
  template <typename Matrix>
  void add_matrix(const Matrix& m) {
    for (int c = 0; c < static_cast<int>(m.cols()); ++c)
      for (int r = 0; r < static_cast<int>(m.rows()); ++r) add(m(r, c));
  }
  constexpr std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace est

#pragma once
// xoshiro128** 1.1 (Blackman and Vigna, "Scrambled linear pseudorandom number generators", 2021): 128-bit state,
// period 2^128 - 1, 32-bit outputs; seeded through splitmix64 so any 64-bit seed gives a well-mixed state.
// Independent streams come from jump() (2^64 steps) and long_jump() (2^96 steps), never from reseeding.
#include <cstdint>

namespace est {

class Xoshiro128ss {
 public:
  using result_type = std::uint32_t;

  constexpr explicit Xoshiro128ss(std::uint64_t seed = 0) : s_{} { reseed(seed); }

  // Stream `stream` of `seed`: the state after `stream` jumps of 2^64 steps, so streams never overlap for fewer than
  // 2^64 draws each. O(stream) jumps: meant for the few streams of a run (particle set, robots, sensor simulators).
  static constexpr Xoshiro128ss stream(std::uint64_t seed, std::uint32_t stream) {
    Xoshiro128ss g(seed);
    for (std::uint32_t i = 0; i < stream; ++i) g.jump();
    return g;
  }

  // A generator in exactly this state (for known-answer tests against the reference implementation).
  static constexpr Xoshiro128ss from_state(std::uint32_t s0, std::uint32_t s1, std::uint32_t s2, std::uint32_t s3) {
    Xoshiro128ss g;
    g.s_[0] = s0;
    g.s_[1] = s1;
    g.s_[2] = s2;
    g.s_[3] = s3;
    return g;
  }

  constexpr void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (int i = 0; i < 4; i += 2) {
      const std::uint64_t z = splitmix64(x);
      s_[i] = static_cast<std::uint32_t>(z);
      s_[i + 1] = static_cast<std::uint32_t>(z >> 32);
    }
    if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0u) s_[0] = 1u;  // the all-zero state is a fixed point
  }

  constexpr std::uint32_t operator()() { return next(); }

  constexpr std::uint32_t next() {
    const std::uint32_t result = rotl(s_[1] * 5u, 7) * 9u;
    const std::uint32_t t = s_[1] << 9;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 11);
    return result;
  }

  // Uniform on [0, 1) with 24 random bits: every value is an exact float, the same on every target.
  constexpr float uniform() { return static_cast<float>(next() >> 8) * 0x1.0p-24f; }
  // Uniform on (0, 1]: safe to take the logarithm of.
  constexpr float uniform_open_zero() { return static_cast<float>((next() >> 8) + 1u) * 0x1.0p-24f; }
  // Uniform on [lo, hi).
  constexpr float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n) by Lemire's multiply-shift; the bias is below n / 2^32, and the time is constant.
  constexpr std::uint32_t below(std::uint32_t n) {
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(next()) * n) >> 32);
  }

  constexpr void jump() { apply_jump(kJump); }
  constexpr void long_jump() { apply_jump(kLongJump); }

  constexpr bool operator==(const Xoshiro128ss& o) const {
    return s_[0] == o.s_[0] && s_[1] == o.s_[1] && s_[2] == o.s_[2] && s_[3] == o.s_[3];
  }
  constexpr bool operator!=(const Xoshiro128ss& o) const { return !(*this == o); }

 private:
  static constexpr std::uint32_t kJump[4] = {0x8764000bu, 0xf542d2d3u, 0x6fa035c3u, 0x77f2db5bu};
  static constexpr std::uint32_t kLongJump[4] = {0xb523952eu, 0x0b6f099fu, 0xccf5a0efu, 0x1c580662u};

  static constexpr std::uint32_t rotl(std::uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

  static constexpr std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

  constexpr void apply_jump(const std::uint32_t (&table)[4]) {
    std::uint32_t t[4] = {0u, 0u, 0u, 0u};
    for (std::uint32_t word : table) {
      for (int b = 0; b < 32; ++b) {
        if (word & (1u << b)) {
          t[0] ^= s_[0];
          t[1] ^= s_[1];
          t[2] ^= s_[2];
          t[3] ^= s_[3];
        }
        next();
      }
    }
    s_[0] = t[0];
    s_[1] = t[1];
    s_[2] = t[2];
    s_[3] = t[3];
  }

  std::uint32_t s_[4];
};

// The generator every firmware component takes by reference.
using Rng = Xoshiro128ss;

}  // namespace est

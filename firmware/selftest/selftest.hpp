#pragma once
// The self-test workload: fixed, seeded runs through the firmware, each reduced to a digest of its outputs' bits.
// The same code runs on the host and on every board; equal digests prove bit-identical results.
#include <cstdint>

namespace est::selftest {

struct Section {
  const char* name;
  std::uint64_t (*run)();
  std::uint64_t expected;  // the host build's digest when the section was last changed on purpose
};

struct Result {
  const char* name;
  std::uint64_t digest;
  std::uint64_t expected;
  bool ok() const { return digest == expected; }
};

inline constexpr int kMaxSections = 32;

// Runs every section; returns how many ran (<= kMaxSections).
int run_all(Result (&out)[kMaxSections]);
// Digest of all section digests, in order.
std::uint64_t combined(const Result* results, int count);

// Sections, one file each.
std::uint64_t section_rng();
std::uint64_t section_gaussian_propagation();
std::uint64_t section_samplers();
std::uint64_t section_motion_b();
std::uint64_t section_sensors();
std::uint64_t section_beam_table();
std::uint64_t section_motion_a();
std::uint64_t section_ekf();
std::uint64_t section_mcl();
std::uint64_t section_mcl_recovery();
std::uint64_t section_loop();
std::uint64_t section_loop_ekf();
std::uint64_t section_loop_velocity();
std::uint64_t section_loop_odometry();
std::uint64_t section_loop_bicycle();
std::uint64_t section_loop_omni();
std::uint64_t section_loop_holonomic();
std::uint64_t section_coop_ekf();

}  // namespace est::selftest

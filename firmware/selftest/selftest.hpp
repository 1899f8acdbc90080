#pragma once
// The self-test workload: fixed, seeded runs through the firmware, each reduced to a digest of its outputs' bits.
// The same code runs on the host and on every board; equal digests prove bit-identical results.
#include <cstdint>

#include "est/util/trace.hpp"

namespace est::selftest {

// A traced section names every output of every step (est/util/trace.hpp): its digest is that of its Trace, and the
// host can also write its outputs as a golden trace (tests/golden/<name>.csv).
struct Section {
  const char* name;
  std::uint64_t (*run)();
  std::uint64_t expected;  // the host build's digest when the section was last changed on purpose
  void (*trace)(Trace&) = nullptr;
};

template <void (*Workload)(Trace&)>
std::uint64_t digest_of() {
  Trace t;
  Workload(t);
  return t.value();
}

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
// The sections themselves, in order (count through `n`): the host's tests run the traced ones with a sink.
const Section* sections(int& n);

// Sections, one file each.
std::uint64_t section_rng();
std::uint64_t section_gaussian_propagation();
std::uint64_t section_samplers();
void section_motion_b(Trace& d);
std::uint64_t section_sensors();
std::uint64_t section_beam_table();
std::uint64_t section_beam_cone();
void section_motion_a(Trace& d);
void section_ekf(Trace& d);
void section_mcl(Trace& d);
void section_mcl_recovery(Trace& d);
void section_loop(Trace& d);
void section_loop_ekf(Trace& d);
void section_loop_velocity(Trace& d);
void section_loop_odometry(Trace& d);
void section_loop_bicycle(Trace& d);
void section_loop_steered(Trace& d);
void section_loop_omni(Trace& d);
void section_loop_holonomic(Trace& d);
std::uint64_t section_coop_ekf();

}  // namespace est::selftest

#include "selftest.hpp"

#include "est/util/digest.hpp"

namespace est::selftest {
namespace {

// Each later part of the firmware adds its section here; `expected` is updated only when a change of results is
// intended, and the host, cortex-m4f and cortex-m7 builds must all reproduce it.
constexpr Section kSections[] = {
    {"rng", section_rng, 0x29befb971cbc5ca9ull},
    {"gaussian_propagation", section_gaussian_propagation, 0x6885d4b16f70beb5ull},
    {"samplers", section_samplers, 0x4c90acd00e9ea70aull},
    {"motion_b", digest_of<section_motion_b>, 0x36f36c772b29fce4ull, section_motion_b},
    {"sensors", section_sensors, 0x473631f183c83d2eull},
    {"beam_table", section_beam_table, 0xcb7de31e0c02c7a1ull},
    {"beam_cone", section_beam_cone, 0x782f25021ccbeb05ull},
    {"motion_a", digest_of<section_motion_a>, 0x651a71140c8e686eull, section_motion_a},
    {"ekf", digest_of<section_ekf>, 0x2dd3334a6b0cb290ull, section_ekf},
    {"mcl", digest_of<section_mcl>, 0xabc6252fa09c079dull, section_mcl},
    {"mcl_recovery", digest_of<section_mcl_recovery>, 0xdb4d7895ed746455ull, section_mcl_recovery},
    {"loop", digest_of<section_loop>, 0x870db31cd4493ac9ull, section_loop},
    {"loop_ekf", digest_of<section_loop_ekf>, 0xf88f46bfa9fe531cull, section_loop_ekf},
    {"loop_velocity", digest_of<section_loop_velocity>, 0x68a50cd02699c7e3ull, section_loop_velocity},
    {"loop_odometry", digest_of<section_loop_odometry>, 0x44e5a039ff0d842dull, section_loop_odometry},
    {"loop_bicycle", digest_of<section_loop_bicycle>, 0xa82330d1e09e380dull, section_loop_bicycle},
    {"loop_omni", digest_of<section_loop_omni>, 0x3e907e424f4e37b4ull, section_loop_omni},
    {"loop_holonomic", digest_of<section_loop_holonomic>, 0x1c686210d16283bcull, section_loop_holonomic},
    {"loop_steered", digest_of<section_loop_steered>, 0x36c1b49d602c9e20ull, section_loop_steered},
    {"coop_ekf", section_coop_ekf, 0xc0451a131d4be0f9ull},
};

}  // namespace

int run_all(Result (&out)[kMaxSections]) {
  int n = 0;
  for (const Section& s : kSections) {
    if (n == kMaxSections) break;
    out[n] = Result{s.name, s.run(), s.expected};
    ++n;
  }
  return n;
}

const Section* sections(int& n) {
  n = static_cast<int>(sizeof kSections / sizeof kSections[0]);
  return kSections;
}

std::uint64_t combined(const Result* results, int count) {
  Digest d;
  for (int i = 0; i < count; ++i) {
    d.add_u32(static_cast<std::uint32_t>(results[i].digest));
    d.add_u32(static_cast<std::uint32_t>(results[i].digest >> 32));
  }
  return d.value();
}

}  // namespace est::selftest

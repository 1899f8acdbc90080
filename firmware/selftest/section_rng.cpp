#include "est/random/xoshiro128.hpp"
#include "est/util/digest.hpp"
#include "selftest.hpp"

namespace est::selftest {

// Raw outputs, uniform floats and jumped streams of the generator.
std::uint64_t section_rng() {
  Digest d;
  Rng a(20261122u);
  for (int i = 0; i < 4096; ++i) d.add_u32(a());
  for (int i = 0; i < 4096; ++i) d.add(a.uniform(-3.0f, 5.0f));
  for (std::uint32_t k = 0; k < 4; ++k) {
    Rng s = Rng::stream(7u, k);
    for (int i = 0; i < 64; ++i) d.add_u32(s.below(1000u));
  }
  return d.value();
}

}  // namespace est::selftest

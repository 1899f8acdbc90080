#pragma once
// Decimal numbers as strtod reads them, exactly, without newlib's strtod (which allocates: the heap gate refuses it):
// [+-]digits[.digits][(e|E)[+-]digits], the whole text. Clinger's fast path: with the significand M < 2^53 and
// |exponent| <= 22, M * 10^k and M / 10^k are single correctly rounded IEEE operations on exact operands, hence the
// correctly rounded value strtod gives (software double on the board rounds the same). Other numbers (more than
// 15-16 significant digits, hex, inf, nan) are refused rather than read differently; a map's YAML never needs them.
#include <cstddef>
#include <cstdint>

namespace board {

inline bool parse_decimal(const char* s, std::size_t n, double& out) {
  static constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  std::size_t i = 0;
  bool negative = false;
  if (i < n && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  std::uint64_t m = 0;
  int digits = 0, exp10 = 0;
  bool any = false;
  const auto digit = [&](char c) { return c >= '0' && c <= '9'; };
  for (; i < n && digit(s[i]); ++i) {
    any = true;
    if (m == 0 && s[i] == '0') continue;  // leading zeros
    if (++digits > 19) return false;
    m = m * 10u + static_cast<std::uint64_t>(s[i] - '0');
  }
  if (i < n && s[i] == '.') {
    for (++i; i < n && digit(s[i]); ++i) {
      any = true;
      --exp10;
      if (m == 0 && s[i] == '0') continue;
      if (++digits > 19) return false;
      m = m * 10u + static_cast<std::uint64_t>(s[i] - '0');
    }
  }
  if (!any) return false;
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < n && (s[i] == '+' || s[i] == '-')) eneg = s[i++] == '-';
    int e = 0, edigits = 0;
    for (; i < n && digit(s[i]); ++i) {
      if (++edigits > 4) return false;
      e = e * 10 + (s[i] - '0');
    }
    if (edigits == 0) return false;
    exp10 += eneg ? -e : e;
  }
  if (i != n) return false;
  if (m == 0) {
    out = negative ? -0.0 : 0.0;
    return true;
  }
  if (m > (std::uint64_t{1} << 53) || exp10 < -22 || exp10 > 22) return false;
  const double v = static_cast<double>(m);
  const double r = exp10 >= 0 ? v * kPow10[exp10] : v / kPow10[-exp10];
  out = negative ? -r : r;
  return true;
}

}  // namespace board

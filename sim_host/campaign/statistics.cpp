#include "campaign/statistics.hpp"

#include <algorithm>
#include <stdexcept>

namespace sim::campaign {

MetricSummary summarize(const std::vector<SeedValue>& values, Worst worst) {
  if (values.empty()) throw std::invalid_argument("summarize: no values");
  std::vector<double> v;
  v.reserve(values.size());
  double sum = 0.0;
  for (const SeedValue& s : values) {
    v.push_back(s.value);
    sum += s.value;
  }
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  MetricSummary m;
  m.count = n;
  m.mean = sum / static_cast<double>(n);
  m.median = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  // ceil(0.95 n) in integers: (95 n + 99) / 100.
  m.p95 = v[std::max<std::size_t>(1, (95 * n + 99) / 100) - 1];
  m.min = v.front();
  m.max = v.back();
  const SeedValue* w = &values.front();
  for (const SeedValue& s : values) {
    const bool worse = worst == Worst::largest ? s.value > w->value : s.value < w->value;
    if (worse || (s.value == w->value && s.seed < w->seed)) w = &s;
  }
  m.worst_seed = w->seed;
  m.worst_value = w->value;
  return m;
}

}  // namespace sim::campaign

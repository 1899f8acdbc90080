#pragma once
// The statistics of one metric over a campaign's seeds: mean, median, 95th percentile, extremes and the worst seed.
// Host only.
#include <cstdint>
#include <vector>

namespace sim::campaign {

struct SeedValue {
  std::uint64_t seed = 0;
  double value = 0.0;
};

// Which end of a metric is worse: errors, times and counts are worse when larger; a few are better when larger
// (higher_is_better() in aggregate.cpp names them).
enum class Worst { largest, smallest };

struct MetricSummary {
  std::size_t count = 0;
  double mean = 0.0;
  double median = 0.0;  // of an even count: the mean of the two middle values
  double p95 = 0.0;     // nearest rank: the ceil(0.95 n)-th smallest value
  double min = 0.0;
  double max = 0.0;
  std::uint64_t worst_seed = 0;  // the lowest seed among equally bad ones
  double worst_value = 0.0;
};

// The summary of `values` (at least one; std::invalid_argument when empty).
MetricSummary summarize(const std::vector<SeedValue>& values, Worst worst);

}  // namespace sim::campaign

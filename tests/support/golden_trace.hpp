#pragma once
// Golden traces (issue 14): a traced workload's outputs (est/util/trace.hpp) as CSV rows `step,quantity,value`,
// stored in tests/golden/<workload>.csv and compared with stated tolerances, so a change of results shows how far
// each quantity moved, not only that a digest changed (PX4 ekf2 keeps its replays' traces beside its tests the same
// way). Values are binary32 outputs written with %.17g (the float's exact value as a double); counts are exact.
//
// To keep the files small a golden keeps every stride-th step of each scope (steps that have outputs, counted in
// order) (chosen when it is written, so
// that about kGoldenRowTarget rows remain, and stated in its header), the last step of every scope (the counters
// and the end state), and at most kGoldenRepeats rows of one quantity within a step (the first particles of a set).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "est/util/trace.hpp"

namespace est::test {

struct TraceRow {
  std::uint32_t step = 0;
  std::string quantity;  // scope.name[index]
  double value = 0.0;
};

// Collects a workload's rows in memory.
class TraceRecorder final : public TraceSink {
 public:
  void row(std::uint32_t step, const char* scope, const char* name, std::int32_t index, double value) override;
  std::vector<TraceRow> rows;
};

inline constexpr std::size_t kGoldenRowTarget = 400;
inline constexpr int kGoldenRepeats = 16;

// The rows a golden of this stride keeps; the smallest stride of 1, 2, 5, 10, 20, 50, ... keeping at most the target.
std::vector<TraceRow> golden_rows(const std::vector<TraceRow>& all, std::uint32_t stride);
std::uint32_t golden_stride(const std::vector<TraceRow>& all);

struct GoldenFile {
  std::uint32_t stride = 1;
  std::vector<TraceRow> rows;
  std::string error;  // empty when read
};
GoldenFile read_golden(const std::string& path);
// Writes the golden of `all`: header, stride, kept rows.
void write_golden(const std::string& path, const std::string& workload, const std::vector<TraceRow>& all);

// |new - golden| <= abs + rel * |golden| for every row.
struct Tolerance {
  double abs = 0.0;
  double rel = 1e-9;
};

// The deviation of one quantity (a column: the quantity less its index) over the rows compared.
struct ColumnDeviation {
  std::string column;
  std::size_t rows = 0;
  double max_abs = 0.0;
  double max_rel = 0.0;
};

struct Comparison {
  bool ok = true;
  std::vector<ColumnDeviation> columns;  // in order of first appearance
  std::string failure;                   // the first row out of tolerance, or the first row that does not line up
  std::size_t rows_over = 0;
  std::string report(const std::string& workload) const;  // the failure and every column's deviation
};

// Compares the golden's rows with the same selection of a new run's rows (`all`, subsampled by the golden's stride).
Comparison compare_with_golden(const GoldenFile& golden, const std::vector<TraceRow>& all, const Tolerance& tol);

}  // namespace est::test

#include "golden_trace.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

namespace est::test {
namespace {

std::string scope_of(const std::string& quantity) {
  const std::size_t dot = quantity.find('.');
  return dot == std::string::npos ? std::string() : quantity.substr(0, dot);
}

std::string column_of(const std::string& quantity) {
  const std::size_t bracket = quantity.find('[');
  return bracket == std::string::npos ? quantity : quantity.substr(0, bracket);
}

std::string format_value(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

void TraceRecorder::row(std::uint32_t step, const char* scope, const char* name, std::int32_t index, double value) {
  std::string q;
  if (scope[0] != '\0') q = std::string(scope) + ".";
  q += name;
  if (index >= 0) q += "[" + std::to_string(index) + "]";
  rows.push_back({step, std::move(q), value});
}

std::vector<TraceRow> golden_rows(const std::vector<TraceRow>& all, std::uint32_t stride) {
  // Per scope: the ordinal of each step that has outputs (so a workload tracing every 20th step still keeps some),
  // and the last such step.
  std::map<std::string, std::map<std::uint32_t, std::uint32_t>> ordinal;
  std::map<std::string, std::uint32_t> last_step;
  for (const TraceRow& r : all) {
    const std::string scope = scope_of(r.quantity);
    auto& steps = ordinal[scope];
    steps.emplace(r.step, static_cast<std::uint32_t>(steps.size()));
    std::uint32_t& s = last_step[scope];
    if (r.step > s) s = r.step;
  }
  std::vector<TraceRow> kept;
  std::map<std::pair<std::string, std::uint32_t>, int> repeats;
  for (const TraceRow& r : all) {
    const std::string scope = scope_of(r.quantity);
    if (ordinal[scope][r.step] % stride != 0 && r.step != last_step[scope]) continue;
    if (++repeats[{scope + "/" + r.quantity, r.step}] > kGoldenRepeats) continue;
    kept.push_back(r);
  }
  return kept;
}

std::uint32_t golden_stride(const std::vector<TraceRow>& all) {
  const std::uint32_t strides[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
  for (std::uint32_t s : strides)
    if (golden_rows(all, s).size() <= kGoldenRowTarget) return s;
  return 1000;
}

GoldenFile read_golden(const std::string& path) {
  GoldenFile g;
  std::ifstream in(path);
  if (!in) {
    g.error = "cannot open " + path;
    return g;
  }
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.rfind("# stride ", 0) == 0) {
      g.stride = static_cast<std::uint32_t>(std::stoul(line.substr(9)));
      continue;
    }
    if (line.empty() || line[0] == '#' || line == "step,quantity,value") continue;
    const std::size_t a = line.find(','), b = line.rfind(',');
    if (a == std::string::npos || a == b) {
      g.error = path + ":" + std::to_string(line_no) + ": not step,quantity,value";
      return g;
    }
    TraceRow r;
    r.step = static_cast<std::uint32_t>(std::stoul(line.substr(0, a)));
    r.quantity = line.substr(a + 1, b - a - 1);
    r.value = std::strtod(line.c_str() + b + 1, nullptr);
    g.rows.push_back(std::move(r));
  }
  if (g.stride == 0) g.error = path + ": stride 0";
  return g;
}

void write_golden(const std::string& path, const std::string& workload, const std::vector<TraceRow>& all) {
  const std::uint32_t stride = golden_stride(all);
  std::ofstream out(path);
  out << "# golden trace of the self-test workload " << workload
      << " (firmware/selftest): outputs as %.17g (each float exactly), counts exact\n"
      << "# kept: every stride-th step of each scope, its last step, at most " << kGoldenRepeats
      << " rows of one quantity per step\n"
      << "# regenerate: EST_UPDATE_GOLDEN=1 build/host/bin/test_determinism, and say why in the commit\n"
      << "# stride " << stride << "\n"
      << "step,quantity,value\n";
  for (const TraceRow& r : golden_rows(all, stride)) out << r.step << ',' << r.quantity << ',' << format_value(r.value) << '\n';
}

Comparison compare_with_golden(const GoldenFile& golden, const std::vector<TraceRow>& all, const Tolerance& tol) {
  Comparison c;
  const std::vector<TraceRow> fresh = golden_rows(all, golden.stride);
  std::map<std::string, std::size_t> index;
  const std::size_t n = golden.rows.size() < fresh.size() ? golden.rows.size() : fresh.size();
  for (std::size_t i = 0; i < n; ++i) {
    const TraceRow& g = golden.rows[i];
    const TraceRow& f = fresh[i];
    if (g.step != f.step || g.quantity != f.quantity) {
      c.ok = false;
      c.failure = "row " + std::to_string(i + 1) + ": golden has step " + std::to_string(g.step) + " " + g.quantity +
                  ", the run step " + std::to_string(f.step) + " " + f.quantity + " (the outputs no longer line up)";
      return c;
    }
    const std::string col = column_of(g.quantity);
    auto it = index.find(col);
    if (it == index.end()) {
      it = index.emplace(col, c.columns.size()).first;
      c.columns.push_back({col, 0, 0.0, 0.0});
    }
    ColumnDeviation& d = c.columns[it->second];
    ++d.rows;
    const double dev = std::fabs(f.value - g.value);
    const double rel = g.value != 0.0 ? dev / std::fabs(g.value) : (dev == 0.0 ? 0.0 : std::numeric_limits<double>::infinity());
    // NaN equals NaN here: a golden NaN is a value the workload produced.
    const bool same_nan = std::isnan(f.value) && std::isnan(g.value);
    if (!same_nan) {
      if (dev > d.max_abs || std::isnan(dev)) d.max_abs = dev;
      if (rel > d.max_rel || std::isnan(rel)) d.max_rel = rel;
    }
    if (!same_nan && !(dev <= tol.abs + tol.rel * std::fabs(g.value))) {
      ++c.rows_over;
      if (c.ok) {
        c.ok = false;
        c.failure = "row " + std::to_string(i + 1) + " (step " + std::to_string(g.step) + "), column " + g.quantity +
                    ": golden " + format_value(g.value) + ", now " + format_value(f.value) + " (abs " +
                    format_value(dev) + ", rel " + format_value(rel) + ")";
      }
    }
  }
  if (golden.rows.size() != fresh.size() && c.ok) {
    c.ok = false;
    c.failure = "the golden has " + std::to_string(golden.rows.size()) + " rows, the run " +
                std::to_string(fresh.size());
  }
  return c;
}

std::string Comparison::report(const std::string& workload) const {
  std::ostringstream s;
  s << workload << ": " << (ok ? "within tolerance" : failure);
  if (rows_over > 1) s << " (" << rows_over << " rows out of tolerance)";
  s << "\n  column: rows, max abs deviation, max rel deviation\n";
  for (const ColumnDeviation& d : columns)
    s << "  " << d.column << ": " << d.rows << ", " << format_value(d.max_abs) << ", " << format_value(d.max_rel)
      << "\n";
  return s.str();
}

}  // namespace est::test

#pragma once
// Reading estimator_node's summary (the counts it prints on stderr when it stops): for the programs and tests that
// run a node and check what it counted. Host only.
#include <cstdlib>
#include <sstream>
#include <string>

namespace node {

// The value of `key=` on the summary line that starts with `line` (e.g. "  rejects.steering:"), -1 when absent.
inline long long summary_value(const std::string& summary, const std::string& line, const std::string& key) {
  std::istringstream in(summary);
  std::string l;
  while (std::getline(in, l)) {
    if (l.compare(0, line.size(), line) != 0) continue;
    const std::size_t at = l.find(" " + key + "=");
    if (at == std::string::npos) return -1;
    return std::atoll(l.c_str() + at + key.size() + 2);
  }
  return -1;
}

}  // namespace node

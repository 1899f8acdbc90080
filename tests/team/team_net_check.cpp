// The network test's judge (tests/team/run-team-netns): compares what each robot's estimator_node wrote over the
// network with the simulator's in-process lockstep run of the same team.
//   team_net_check LOCKSTEP.csv TRUTH.csv NODE_DIR ROBOTS exact
//     every NODE_DIR/node_<a>.csv equals LOCKSTEP.csv line for line (the same estimate bit for bit), and no node
//     missed, refused or dropped a message
//   team_net_check LOCKSTEP.csv TRUTH.csv NODE_DIR ROBOTS lossy MAX_RMSE_M MAX_RATIO [SILENT FROM TO]
//     every loss is counted (at node a, the steps closed without robot b's message are b's dropped messages plus the
//     late ones), and each robot's position RMSE from its own node stays within MAX_RMSE_M and within MAX_RATIO
//     times the lockstep run's; with robot SILENT silent for steps FROM..TO, every other node flags those steps
//     (status bit 12, a teammate predicted only) and has the silent robot back within MAX_RMSE_M at the end
// Prints the figures; exit status 0 when every check holds.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream f(path);
  if (!f) {
    std::fprintf(stderr, "team_net_check: cannot read %s\n", path.c_str());
    std::exit(2);
  }
  std::vector<std::string> v;
  for (std::string l; std::getline(f, l);) v.push_back(l);
  return v;
}

std::vector<std::string> fields(const std::string& l) {
  std::vector<std::string> v;
  std::stringstream s(l);
  for (std::string x; std::getline(s, x, ',');) v.push_back(x);
  return v;
}

std::map<std::string, long> counts_of(const std::string& path) {
  std::map<std::string, long> m;
  for (const std::string& l : lines_of(path)) {
    std::istringstream s(l);
    std::string k;
    long v = 0;
    if (s >> k >> v) m[k] = v;
  }
  return m;
}

// Position RMSE of robot `a` in an estimates file (seq, status, dim, mean...) against the truth (trajectory.csv:
// t, then 8 columns per robot starting with true_x, true_y; row k is step k).
double rmse(const std::vector<std::string>& est, const std::vector<std::string>& truth, int a, int* steps) {
  double s = 0.0;
  int n = 0;
  for (std::size_t i = 1; i < est.size(); ++i) {
    const std::vector<std::string> e = fields(est[i]);
    const long seq = std::strtol(e[0].c_str(), nullptr, 10);
    if (seq < 1 || static_cast<std::size_t>(seq) >= truth.size()) continue;
    const std::vector<std::string> t = fields(truth[static_cast<std::size_t>(seq)]);
    const double dx = std::strtod(e[3 + 2 * static_cast<std::size_t>(a)].c_str(), nullptr) -
                      std::strtod(t[1 + 8 * static_cast<std::size_t>(a)].c_str(), nullptr);
    const double dy = std::strtod(e[4 + 2 * static_cast<std::size_t>(a)].c_str(), nullptr) -
                      std::strtod(t[2 + 8 * static_cast<std::size_t>(a)].c_str(), nullptr);
    s += dx * dx + dy * dy;
    ++n;
  }
  *steps = n;
  return n > 0 ? std::sqrt(s / n) : 1e9;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: team_net_check LOCKSTEP.csv TRUTH.csv NODE_DIR ROBOTS exact|lossy [MAX_RMSE RATIO]\n");
    return 2;
  }
  const std::vector<std::string> lockstep = lines_of(argv[1]), truth = lines_of(argv[2]);
  const std::string dir = argv[3], mode = argv[5];
  const int R = std::atoi(argv[4]);
  bool ok = true;
  std::vector<std::map<std::string, long>> counts;
  for (int a = 0; a < R; ++a) counts.push_back(counts_of(dir + "/node_" + std::to_string(a) + ".counts"));
  for (int a = 0; a < R; ++a) {
    const std::vector<std::string> node = lines_of(dir + "/node_" + std::to_string(a) + ".csv");
    std::map<std::string, long>& c = counts[static_cast<std::size_t>(a)];
    if (mode == "exact") {
      std::size_t differ = node.size() == lockstep.size() ? 0 : 1;
      for (std::size_t i = 0; i < node.size() && i < lockstep.size(); ++i) differ += node[i] != lockstep[i] ? 1u : 0u;
      std::printf("node %d: %zu steps, %zu lines differ from the lockstep run; %ld received in order, %ld out of "
                  "order, %ld late\n", a, node.size() - 1, differ, c["in_order"], c["out_of_order"], c["late"]);
      const long lost = c["late"] + c["malformed"] + c["duplicate"] + c["unknown_robot"] + c["undecodable"];
      ok = ok && differ == 0 && lost == 0;
      continue;
    }
    // Every loss counted: steps closed without b at node a = b's drops + late arrivals at a.
    long missing_others = 0, dropped_others = 0;
    for (int b = 0; b < R; ++b)
      if (b != a) {
        missing_others += c["missing_" + std::to_string(b)];
        dropped_others += counts[static_cast<std::size_t>(b)]["dropped_out"];
      }
    int n = 0, n0 = 0;
    const double e = rmse(node, truth, a, &n), e0 = rmse(lockstep, truth, a, &n0);
    const double max_rmse = argc > 6 ? std::atof(argv[6]) : 0.3, ratio = argc > 7 ? std::atof(argv[7]) : 3.0;
    std::printf("node %d: %d steps; teammates' steps missing %ld = %ld dropped + %ld late; own missing %ld; robot %d "
                "RMSE %.3f m (lossless %.3f m)\n", a, n, missing_others, dropped_others, c["late"],
                c["missing_" + std::to_string(a)], a, e, e0);
    ok = ok && missing_others == dropped_others + c["late"] && c["missing_" + std::to_string(a)] == 0;
    ok = ok && e <= max_rmse && e <= ratio * e0 && n == n0;
    if (argc > 10 && std::atoi(argv[8]) != a) {
      const int silent = std::atoi(argv[8]);
      const long from = std::atol(argv[9]), to = std::atol(argv[10]);
      long flagged = 0, in_gap = 0;
      for (std::size_t i = 1; i < node.size(); ++i) {
        const std::vector<std::string> f = fields(node[i]);
        const long seq = std::strtol(f[0].c_str(), nullptr, 10);
        if (seq < from || seq > to) continue;
        ++in_gap;
        flagged += (std::strtoul(f[1].c_str(), nullptr, 16) & 0x1000ul) != 0u ? 1 : 0;
      }
      // The silent robot at the end, from this node: it rejoined.
      const std::vector<std::string> last = fields(node.back());
      const long last_seq = std::strtol(last[0].c_str(), nullptr, 10);
      const std::vector<std::string> t = fields(truth[static_cast<std::size_t>(last_seq)]);
      const std::size_t k = static_cast<std::size_t>(silent);
      const double dx = std::strtod(last[3 + 2 * k].c_str(), nullptr) - std::strtod(t[1 + 8 * k].c_str(), nullptr);
      const double dy = std::strtod(last[4 + 2 * k].c_str(), nullptr) - std::strtod(t[2 + 8 * k].c_str(), nullptr);
      const double back = std::sqrt(dx * dx + dy * dy);
      std::printf("  robot %d silent for steps %ld-%ld: %ld of %ld flagged here; at the end %.3f m off\n", silent,
                  from, to, flagged, in_gap, back);
      ok = ok && in_gap == to - from + 1 && flagged == in_gap && back <= max_rmse;
    }
  }
  std::printf("%s\n", ok ? "team network check: OK" : "team network check: FAILED");
  return ok ? 0 : 1;
}

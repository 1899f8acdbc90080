// estimator_node: the firmware's filter loop on the host (node/node.hpp). Live, it reads sensor inputs from
// SocketCAN (--can) and/or LCM (--lcm) and publishes estimates on LCM (and CAN with --can-out); with --replay (an
// LCM log) or --replay-can (a candump log) it runs the inputs through the same pipeline in lockstep, as fast as it
// can, and writes the estimates to an LCM log (--out) or a candump log (--out-can), deterministically.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <exception>

#include "node/node.hpp"
#include "node/team_node.hpp"

namespace {

// --filter coop-ekf: one robot's node of a team (node/team_node.hpp), with its own options.
bool team_mode(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--filter=coop-ekf") == 0) return true;
    if (std::strcmp(argv[i], "--filter") == 0 && i + 1 < argc && std::strcmp(argv[i + 1], "coop-ekf") == 0) return true;
  }
  return false;
}

// Parses the options into a Config, runs a Node on it and prints its summary: the same for both kinds of node.
template <typename Node, typename Config, typename Add, typename Finish>
int run(CLI::App& app, int argc, char** argv, Add add, Finish finish) {
  Config config;
  add(app, config);
  try {
    app.parse(argc, argv);
    finish(app, config);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    Node n(config);
    const int rc = n.run();
    if (!config.quiet) n.print_summary(stderr);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "estimator_node: %s\n", e.what());
    return 1;
  }
}

int run_team_node(int argc, char** argv) {
  CLI::App app{
      "estimator_node --filter coop-ekf: one robot's node of a team running cooperative EKF-SLAM (holonomic point "
      "robots, point landmarks, ranges and bearings). The robot's own step messages come in on EST_TEAM_OWN_<id> "
      "and go out to the team on EST_TEAM; the teammates' come in from EST_TEAM through the team validator; every "
      "node holds the whole team's estimate, and nodes that receive the same messages hold the same, bit for bit."};
  return run<node::TeamNode, node::TeamNodeConfig>(
      app, argc, argv, node::add_team_node_options,
      [](const CLI::App&, node::TeamNodeConfig& c) { node::finish_team_node_options(c); });
}

}  // namespace

int main(int argc, char** argv) {
  if (team_mode(argc, argv)) return run_team_node(argc, argv);
  CLI::App app{
      "estimator_node: the firmware's filter loop (augmented MCL on a map, or EKF localization on landmarks, with "
      "any of six motion models) on the host.\n"
      "Live: sensor inputs from SocketCAN (--can) and/or LCM (--lcm), estimates out on LCM (pose_estimate_t, "
      "status_t) and CAN (--can-out); stops on SIGINT/SIGTERM (or --duration) with a summary of counts on stderr.\n"
      "Replay: --replay IN.lcmlog or --replay-can IN.candump runs a log through the loop in lockstep, as fast as "
      "possible; the same log and options give the same outputs, bit for bit.\n"
      "Team: --filter coop-ekf runs one robot's node of a cooperative EKF-SLAM team (estimator_node --filter "
      "coop-ekf --help lists its options)."};
  return run<node::Node, node::NodeConfig>(app, argc, argv, node::add_options, node::finish_options);
}

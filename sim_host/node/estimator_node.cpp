// estimator_node: the firmware's filter loop on the host (node/node.hpp). Live, it reads sensor inputs from
// SocketCAN (--can) and/or LCM (--lcm) and publishes estimates on LCM (and CAN with --can-out); with --replay (an
// LCM log) or --replay-can (a candump log) it runs the inputs through the same pipeline in lockstep, as fast as it
// can, and writes the estimates to an LCM log (--out) or a candump log (--out-can), deterministically.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "node/node.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "estimator_node: the firmware's filter loop (augmented MCL on a map, or EKF localization on landmarks, with "
      "any of six motion models) on the host.\n"
      "Live: sensor inputs from SocketCAN (--can) and/or LCM (--lcm), estimates out on LCM (pose_estimate_t, "
      "status_t) and CAN (--can-out); stops on SIGINT/SIGTERM (or --duration) with a summary of counts on stderr.\n"
      "Replay: --replay IN.lcmlog or --replay-can IN.candump runs a log through the loop in lockstep, as fast as "
      "possible; the same log and options give the same outputs, bit for bit."};
  node::NodeConfig config;
  node::add_options(app, config);
  try {
    app.parse(argc, argv);
    node::finish_options(app, config);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    node::Node n(config);
    const int rc = n.run();
    if (!config.quiet) n.print_summary(stderr);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "estimator_node: %s\n", e.what());
    return 1;
  }
}

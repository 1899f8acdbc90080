// reference-coop-slam.elf: the reference cooperative EKF-SLAM rig on the board, for its budgets (instructions per
// step, stack, and through the image's size its RAM and flash): the team's estimator
// (est/team/coop_ekf_estimator.hpp) for R = 2 robots and M = 32 landmarks, range and bearing, on the team workload
// (team_workload.hpp; the landmarks enter the state from the first step's sightings).
//
// The workload (reference_step() is the estimator's step on the messages of both robots):
//  - typical: 32 steps in which each robot measures the other robot and 8 of the landmarks;
//  - 8 steps without measurements (prediction only);
//  - the worst step: each robot's message full, the other robot and 31 landmarks (64 measurements fused; a team
//    message holds 32 measurements, est/team/team_message.hpp, so a robot cannot report all 32 landmarks and the
//    other robot in one step).
// Prints the figures, then "budget KEY VALUE UNIT" lines for check_budgets.cmake, then PASS, or FAIL when a
// measurement was not fused (a workload that went wrong measures nothing).
#include <cstdint>

#include "reference_step.hpp"
#include "stack_paint.hpp"
#include "team_workload.hpp"

namespace {

using Workload = board::TeamWorkload<2, 32, true>;
constexpr int kSeen = 8;

}  // namespace

extern "C" __attribute__((noinline)) void reference_step() { Workload::step(); }

int main() {
  if (!Workload::start()) return board::write("reference-coop-slam: FAIL the estimator refused its configuration\n"), 1;
  auto& s = Workload::state();
  const std::uint32_t accepted0 = s.estimator.slam().counters().accepted;
  board::StepCounts typical, predict;
  board::stack_paint();
  for (int i = 0; i < 32; ++i) {
    Workload::messages(false, kSeen);
    typical.add(board::counted_step());
  }
  for (int i = 0; i < 8; ++i) {
    Workload::messages(true);
    predict.add(board::counted_step());
  }
  const std::uint32_t accepted1 = s.estimator.slam().counters().accepted;
  Workload::messages(false);
  const std::uint64_t worst = board::counted_step();
  const std::uint32_t stack = board::stack_high_water();
  const std::uint32_t fused_typical = accepted1 - accepted0;
  const std::uint32_t fused_worst = s.estimator.slam().counters().accepted - accepted1;

  board::write("reference-coop-slam: R=2 M=32 n=");
  board::write_dec(static_cast<std::uint64_t>(s.estimator.slam().dim()));
  board::write(", ");
  board::write_dec(fused_typical);
  board::write(" measurements fused in the typical steps\n");
  board::write_counts("reference-coop-slam", "typical steps (each robot: the other and 8 landmarks)", typical);
  board::write_counts("reference-coop-slam", "steps that only predict", predict);
  board::write("reference-coop-slam: the worst step (full messages, ");
  board::write_dec(fused_worst);
  board::write(" measurements fused): ");
  board::write_dec(worst);
  board::write(" instructions\nreference-coop-slam: stack of a step (painted): ");
  board::write_dec(stack);
  board::write(" bytes\n");
  board::report_budget("coop.step.typical", typical.mean(), "instructions");
  board::report_budget("coop.step.predict", predict.mean(), "instructions");
  board::report_budget("coop.step.worst", worst, "instructions");
  board::report_budget("coop.stack.step", stack, "bytes");

  const bool ok = fused_typical == 32u * 2u * (1u + kSeen) && fused_worst == static_cast<std::uint32_t>(
                      Workload::kMeasurements) && stack < board::kStackPaintWindow;
  board::write(ok ? "reference-coop-slam: PASS\n" : "reference-coop-slam: FAIL (the workload went wrong)\n");
  return ok ? 0 : 1;
}

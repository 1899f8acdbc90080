// The static stack bound (stack_bound.hpp): the reader and the bound on small call graphs, then each reference image
// of a board (firmware/target/mps2/reference_*_main.cpp): reference_step()'s bound from the board build's call graph
// (with an interrupt at its deepest point) has no unknowable part, is at least the stack the image painted under
// qemu for the same function, and is within
// its budget (firmware/target/mps2/budgets/<board>.txt, stack_bound.KEY, more than 5 % over fails).
// Without the board's build (EST_BOARD_BUILD) the image cases are skipped (exit 77) with a message.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "stack_bound.hpp"

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : "";
}

// f (48 bytes) calls g (16) and h (100); g calls memcpy (no .ci: a leaf helper).
const char* const kGraph = R"ci(graph: { title: "a.cpp"
node: { title: "f" label: "void f()\na.cpp:1:6\n48 bytes (static)" }
node: { title: "g" label: "void g()\na.cpp:2:6\n16 bytes (static)" }
node: { title: "memcpy" label: "memcpy\n<built-in>" shape : ellipse }
edge: { sourcename: "f" targetname: "g" label: "a.cpp:1:20" }
edge: { sourcename: "g" targetname: "memcpy" label: "a.cpp:2:20" }
node: { title: "h" label: "void h()\na.cpp:3:6\n100 bytes (static)" }
edge: { sourcename: "f" targetname: "h" label: "a.cpp:1:30" }
}
)ci";

stackbound::Bound bound_of(const std::string& text, const std::string& root) {
  stackbound::CallGraph g;
  stackbound::add_ci(g, text, "test.ci");
  return stackbound::stack_bound(g, root);
}

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (p == nullptr) return out;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  pclose(p);
  return out;
}

// The value of "KEY VALUE UNIT" in `text` (a budget line of an image's output, or of a budgets file), or -1.
long long value_of(const std::string& text, const std::string& key, bool budget_line) {
  const std::regex re((budget_line ? "budget " : "(^|\n)") + std::regex_replace(key, std::regex(R"(\.)"), "\\.") +
                      R"( ([0-9]+) [a-z]+)");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return -1;
  return std::stoll(m[m.size() - 1]);
}

}  // namespace

TEST_CASE("stack_bound: a function's frame plus its deepest callee's bound, leaf helpers at kLeafFrame") {
  const stackbound::Bound b = bound_of(kGraph, "f");
  CHECK(b.problems.empty());
  CHECK(b.bytes == 48u + 100u);  // h's 100 beats g + memcpy's 16 + 64
  CHECK(b.path == std::vector<std::string>{"f", "h"});
  CHECK(bound_of(kGraph, "g").bytes == 16u + stackbound::kLeafFrame);
}

TEST_CASE("stack_bound: a frame defined in several units counts with its largest") {
  stackbound::CallGraph g;
  stackbound::add_ci(g, kGraph, "a.ci");
  stackbound::add_ci(g, "node: { title: \"h\" label: \"void h()\\na.hpp:3:6\\n120 bytes (static)\" }\n", "b.ci");
  CHECK(stackbound::stack_bound(g, "f").bytes == 48u + 120u);
}

TEST_CASE("stack_bound: what makes a bound unknowable is reported, not guessed") {
  const std::string head = "node: { title: \"f\" label: \"void f()\\na.cpp:1:6\\n8 bytes (static)\" }\n";
  SECTION("a call through a pointer") {
    const auto b = bound_of(head + "node: { title: \"__indirect_call\" label: \"Indirect Call Placeholder\" shape : "
                                   "ellipse }\nedge: { sourcename: \"f\" targetname: \"__indirect_call\" label: \"x\" }\n",
                            "f");
    REQUIRE(b.problems.size() == 1u);
    CHECK(b.problems[0].find("pointer") != std::string::npos);
  }
  SECTION("recursion") {
    const auto b = bound_of(head + "edge: { sourcename: \"f\" targetname: \"f\" label: \"x\" }\n", "f");
    REQUIRE(b.problems.size() == 1u);
    CHECK(b.problems[0].find("recursion") != std::string::npos);
  }
  SECTION("a callee with no frame anywhere") {
    const auto b = bound_of(head + "edge: { sourcename: \"f\" targetname: \"printf\" label: \"x\" }\n", "f");
    REQUIRE(b.problems.size() == 1u);
    CHECK(b.problems[0].find("printf: no frame") != std::string::npos);
  }
  SECTION("a frame of dynamic size; dynamic,bounded is a bound") {
    CHECK(bound_of("node: { title: \"f\" label: \"f\\na.cpp:1:6\\n8 bytes (dynamic)\" }\n", "f").problems.size() == 1u);
    CHECK(bound_of("node: { title: \"f\" label: \"f\\na.cpp:1:6\\n8 bytes (dynamic,bounded)\" }\n", "f").problems.empty());
  }
  SECTION("a line the reader does not understand") {
    CHECK_THROWS(bound_of("node: { label: \"f\" title: \"f\" }\n", "f"));
  }
}

TEST_CASE("stack_bound: each reference image's step, bounded from the call graph, at least its painted stack, "
          "within budget", "[board]") {
  const std::string board = env("EST_BOARD"), build = env("EST_BOARD_BUILD"), budgets_file = env("EST_BUDGETS");
  std::ifstream bf(budgets_file);
  REQUIRE(bf.good());
  const std::string budgets((std::istreambuf_iterator<char>(bf)), std::istreambuf_iterator<char>());
  for (const char* image : {"mcl", "ekf", "coop-slam"}) {
    const std::string prefix = std::string(image) == "coop-slam" ? "coop" : image;
    DYNAMIC_SECTION("reference-" << image) {
      stackbound::CallGraph g;
      REQUIRE(stackbound::add_ci_dir(g, build + "/firmware/target/mps2/CMakeFiles/reference-" + image + ".dir") > 0);
      REQUIRE(stackbound::add_ci_dir(g, build + "/firmware/CMakeFiles/firmware.dir") > 0);
      const stackbound::Bound b = stackbound::stack_bound(g, "reference_step");
      // An interrupt may land at the step's deepest point: the exception entry's frame with the FPU's state (Armv7-M:
      // 26 words and 4 bytes of alignment) and the handler's own bound (the instruction counter's SysTick handler,
      // the one interrupt the images enable) come on top.
      const stackbound::Bound isr = stackbound::stack_bound(g, "est_instruction_counter_systick");
      const std::uint32_t bound = b.bytes + 108u + isr.bytes;
      std::string path;
      for (const std::string& t : b.path)
        path += "\n  " + g.functions.at(t).name + " (" +
                (g.functions.at(t).has_frame ? std::to_string(g.functions.at(t).frame) + " bytes)" : "a leaf helper)");
      INFO("reference_step's bound " << b.bytes << " bytes, by the path:" << path);
      INFO("with an interrupt at the deepest point: " << bound << " bytes");
      std::string problems;
      for (const std::string& p : b.problems) problems += "\n  " + p;
      for (const std::string& p : isr.problems) problems += "\n  " + p;
      INFO("what makes it no bound:" << problems);
      CHECK(b.problems.empty());
      const std::string out = run(std::string(EST_SOURCE_DIR) + "/scripts/run-on-board " + board + " " + build +
                                  "/bin/reference-" + image + ".elf -icount shift=10");
      const long long painted = value_of(out, prefix + ".stack.step", true);
      INFO(out);
      REQUIRE(painted > 0);
      CHECK(static_cast<long long>(bound) >= painted);
      const long long budget = value_of(budgets, "stack_bound." + prefix, false);
      REQUIRE(budget > 0);
      CHECK(static_cast<long long>(bound) * 100 <= budget * 105);
      std::printf("reference-%s on %s: reference_step's stack: bound %u bytes with an interrupt (budget %lld), "
                  "painted %lld bytes\n", image, board.c_str(), bound, budget, painted);
    }
  }
}

int main(int argc, char** argv) {
  const std::string build = env("EST_BOARD_BUILD"), board = env("EST_BOARD");
  if (build.empty() || board.empty()) {
    std::fprintf(stderr, "test_stack_bound: set EST_BOARD and EST_BOARD_BUILD (ctest does)\n");
    return 1;
  }
  if (!std::filesystem::exists(build + "/bin/reference-mcl.elf")) {
    std::vector<char*> args(argv, argv + argc);  // the reader's cases still run; the images' case cannot
    static char skip_board[] = "~[board]";
    args.push_back(skip_board);
    if (Catch::Session().run(static_cast<int>(args.size()), args.data()) != 0) return 1;
    std::printf("SKIP: %s/bin/reference-mcl.elf is missing: build the %s preset first (cmake --preset %s && cmake "
                "--build --preset %s)\n", build.c_str(), board.c_str(), board.c_str(), board.c_str());
    return 77;
  }
  return Catch::Session().run(argc, argv);
}

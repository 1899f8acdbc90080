// Progress on a terminal (sim/progress.hpp): drawn on a terminal after its delay, with simulated time, real-time
// factor and ETA; nothing with quiet or when stderr is not a terminal.
#include <fcntl.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "sim/progress.hpp"

namespace {

// Runs `body` with stderr on a new pseudo-terminal (or on a pipe), and returns what it wrote there.
template <typename F>
std::string stderr_of(bool terminal, F body) {
  int reader = -1, writer = -1;
  if (terminal) {
    reader = posix_openpt(O_RDWR | O_NOCTTY);
    REQUIRE(reader >= 0);
    REQUIRE(grantpt(reader) == 0);
    REQUIRE(unlockpt(reader) == 0);
    writer = open(ptsname(reader), O_RDWR | O_NOCTTY);
  } else {
    int p[2];
    REQUIRE(pipe(p) == 0);
    reader = p[0];
    writer = p[1];
  }
  REQUIRE(writer >= 0);
  std::fflush(stderr);
  const int saved = dup(2);
  dup2(writer, 2);
  body();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  close(writer);
  fcntl(reader, F_SETFL, O_NONBLOCK);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(reader, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  close(reader);
  return out;
}

void simulated_run(sim::Progress& p) {
  for (int k = 1; k <= 30; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    p.update(k * 2.0);
  }
  p.finish();
}

}  // namespace

TEST_CASE("progress on a terminal shows simulated time, real-time factor and ETA", "[progress]") {
  const std::string out = stderr_of(true, [] {
    sim::Progress p("simulate", 60.0, false, sim::Progress::Unit::simulated_s, 0.05);
    CHECK(p.enabled());
    simulated_run(p);
  });
  INFO(out);
  CHECK(out.find("simulate: t ") != std::string::npos);
  CHECK(out.find(" / 60.0 s, ") != std::string::npos);
  CHECK(out.find("x real time, ETA ") != std::string::npos);
  CHECK(out.find("simulate: done in ") != std::string::npos);
  CHECK(out.find("t 2.0 / 60.0") == std::string::npos);  // nothing before the delay
}

TEST_CASE("progress is quiet when asked, when stderr is not a terminal, and for a short run", "[progress]") {
  CHECK(stderr_of(true, [] {
          sim::Progress p("simulate", 60.0, true, sim::Progress::Unit::simulated_s, 0.0);
          CHECK(!p.enabled());
          simulated_run(p);
        }).empty());
  CHECK(stderr_of(false, [] {
          sim::Progress p("simulate", 60.0, false, sim::Progress::Unit::simulated_s, 0.0);
          CHECK(!p.enabled());
          simulated_run(p);
        }).empty());
  CHECK(stderr_of(true, [] {
          sim::Progress p("simulate", 60.0, false, sim::Progress::Unit::simulated_s, 10.0);
          simulated_run(p);  // 0.3 s: done before the delay, nothing drawn
        }).empty());
}

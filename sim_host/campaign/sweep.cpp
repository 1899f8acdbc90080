#include "campaign/sweep.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/progress.hpp"

extern char** environ;

namespace sim::campaign {
namespace fs = std::filesystem;
namespace {

// Starts one seed's run with stdin from /dev/null and stdout and stderr into its run.log; -1 when it cannot start
// (then run.log says why).
pid_t start_seed(const Campaign& c, const Combination& k, std::uint64_t seed, const fs::path& dir) {
  const fs::path out = seed_dir(combination_dir(dir, k), seed);
  fs::create_directories(out);
  fs::remove(out / "exit_status");
  const std::string log = (out / "run.log").string();
  const std::vector<std::string> cmd = seed_command(c, k, seed, dir);
  std::vector<char*> argv;
  for (const std::string& a : cmd) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    std::ofstream(log) << "sim_host sweep: cannot start " << cmd[0] << ": " << std::strerror(rc) << "\n";
    return -1;
  }
  return pid;
}

// The shell's convention: the exit code, or 128 + the signal that ended it.
int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 255;
}

void finish_seed(const Combination& k, std::uint64_t seed, const fs::path& dir, int code, SweepCounts& n) {
  std::ofstream(seed_dir(combination_dir(dir, k), seed) / "exit_status") << code << "\n";
  ++n.done;
  if (code != 0) ++n.failed;
}

}  // namespace

SweepCounts run_sweep(const Campaign& c, const fs::path& dir, std::size_t jobs, bool quiet) {
  if (jobs == 0) throw std::invalid_argument("--jobs must be at least 1");
  const std::vector<Combination> combinations = c.combinations();
  Progress progress("sweep", static_cast<double>(combinations.size() * c.seed_count()), quiet);
  SweepCounts n;
  struct Run {
    const Combination* k;
    std::uint64_t seed;
  };
  std::map<pid_t, Run> running;
  std::size_t next_k = 0;
  std::uint64_t next = c.first_seed;
  bool more = true;
  const auto show = [&] { progress.update(static_cast<double>(n.done), std::to_string(n.failed) + " failed"); };
  while (more || !running.empty()) {
    while (more && running.size() < jobs) {
      const Run r{&combinations[next_k], next};
      if (next != c.last_seed) ++next;
      else {
        next = c.first_seed;
        more = ++next_k < combinations.size();
      }
      const pid_t pid = start_seed(c, *r.k, r.seed, dir);
      if (pid < 0) finish_seed(*r.k, r.seed, dir, 127, n);  // as a shell says of a command it cannot run
      else running[pid] = r;
    }
    show();
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("sim_host sweep: waitpid: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    finish_seed(*it->second.k, it->second.seed, dir, exit_code(status), n);
    running.erase(it);
  }
  show();
  progress.finish();
  return n;
}

}  // namespace sim::campaign

#include "campaign/slurm.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sim::campaign {
namespace fs = std::filesystem;
namespace {

// A word for sh: single-quoted, a quote inside closed, escaped and reopened.
std::string sh_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string slurm_batch_script(const Campaign& c, const fs::path& dir) {
  const std::vector<Combination> combinations = c.combinations();
  const bool grid = !c.grid.empty();
  std::ostringstream s;
  s << "#!/bin/sh\n"
    << "# sim_host campaign: " << c.scenario << ", seeds " << c.first_seed << ".." << c.last_seed;
  if (grid)
    s << " x " << combinations.size() << " parameter combinations, one array task per run (task i: combination\n"
      << "# i / " << c.seed_count() << ", seed " << c.first_seed << " + i % " << c.seed_count() << ")";
  else
    s << ", one array task per seed";
  s << " (written by sim_host sweep --emit-slurm; `sbatch campaign.sbatch`, then\n"
    << "# `sim_host aggregate " << dir.string() << "`).\n"
    << "#SBATCH --job-name=" << fs::path(c.scenario).stem().string() << "-sweep\n";
  if (grid)
    s << "#SBATCH --array=0-" << combinations.size() * c.seed_count() - 1 << "\n";
  else
    s << "#SBATCH --array=" << c.first_seed << "-" << c.last_seed << "\n";
  s << "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << (dir / "slurm-%A_%a.out").string() << "\n";
  if (grid) {
    // The combination's --set options become the positional parameters ("$@"), so each stays one word.
    s << "task=$SLURM_ARRAY_TASK_ID\n"
      << "seed=$((" << c.first_seed << " + task % " << c.seed_count() << "))\n"
      << "case $((task / " << c.seed_count() << ")) in\n";
    for (const Combination& k : combinations) {
      s << "  " << k.index << ") combination=" << sh_quoted(k.name) << "; set --";
      for (const std::string& o : combination_options(k)) s << " " << sh_quoted(o);
      s << " ;;\n";
    }
    s << "  *) echo \"task $task: no such combination\" >&2; exit 2 ;;\n"
      << "esac\n"
      << "out=" << sh_quoted(dir.string()) << "/\"$combination\"/seed-$seed\n";
  } else {
    s << "seed=$SLURM_ARRAY_TASK_ID\n"
      << "out=" << sh_quoted(dir.string()) << "/seed-$seed\n";
  }
  s << "mkdir -p \"$out\" && rm -f \"$out/exit_status\" || exit 1\n"
    << sh_quoted(c.sim_host) << " run " << sh_quoted(c.scenario) << " --seed \"$seed\" --out \"$out\"";
  for (const std::string& o : run_options(c)) s << " " << sh_quoted(o);
  if (grid) s << " \"$@\"";
  s << " >\"$out/run.log\" 2>&1\n"
    << "status=$?\n"
    << "echo \"$status\" >\"$out/exit_status\"\n"
    << "exit \"$status\"\n";
  return s.str();
}

void emit_slurm(const Campaign& c, const fs::path& dir) {
  write_campaign_json(c, dir);
  const fs::path p = dir / "campaign.sbatch";
  std::ofstream f(p);
  f << slurm_batch_script(c, dir);
  if (!f) throw std::runtime_error("cannot write " + p.string());
  f.close();
  fs::permissions(p, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);
}

}  // namespace sim::campaign

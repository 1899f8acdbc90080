// scripts/carmen-vs-mrpt's helper: gives the observations of a rawlog written by MRPT 2.5's carmen2rawlog their
// CARMEN stamps. That carmen2rawlog stamps every observation with the conversion's time, and pf-localization looks
// its ground truth up by stamp (by rawlog entry it always reads row 0). Entry k gets the k / 2-th stamp of TIMES (one
// per scan, seconds): each scan follows its odometry. Built by the script with libmrpt-obs-dev.
// Usage: carmen-mrpt-retime IN.rawlog TIMES OUT.rawlog
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CRawlog.h>

#include <cstdio>
#include <fstream>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: carmen-mrpt-retime IN.rawlog TIMES OUT.rawlog\n");
    return 2;
  }
  mrpt::obs::CRawlog log;
  if (!log.loadFromRawLogFile(argv[1])) return 1;
  std::vector<double> t;
  std::ifstream f(argv[2]);
  for (double v; f >> v;) t.push_back(v);
  if (log.size() != 2 * t.size()) {
    std::fprintf(stderr, "carmen-mrpt-retime: %zu entries for %zu stamps\n", log.size(), t.size());
    return 1;
  }
  for (std::size_t k = 0; k < log.size(); ++k) log.getAsObservation(k)->timestamp = mrpt::Clock::fromDouble(t[k / 2]);
  return log.saveToRawLogFile(argv[3]) ? 0 : 1;
}

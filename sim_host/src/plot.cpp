#include "sim/plot.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

extern char** environ;

namespace sim {
namespace {

// A string as a gnuplot single-quoted literal (a quote inside is doubled).
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    out += c;
    if (c == '\'') out += '\'';
  }
  return out + "'";
}

}  // namespace

int run_program(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void render_scatter_png(const ScatterPlot& plot, const std::string& png_path) {
  namespace fs = std::filesystem;
  const fs::path png(png_path);
  const fs::path script = fs::path(png).replace_extension(".gp");
  {
    std::ofstream gp(script);
    if (!gp) throw std::runtime_error("cannot write gnuplot script " + script.string());
    gp << "set terminal pngcairo size " << plot.width_px << "," << plot.height_px << " enhanced font 'Sans,11'\n";
    gp << "set output " << quoted(png.string()) << "\n";
    gp << "set datafile separator ','\n";
    gp << "set datafile columnheaders\n";  // the CSV's first line names the columns
    gp << "set title " << quoted(plot.title) << " noenhanced\n";
    gp << "set xlabel " << quoted(plot.x_label) << " noenhanced\n";
    gp << "set ylabel " << quoted(plot.y_label) << " noenhanced\n";
    gp << "set grid lc rgb 'gray85'\n";
    gp << "set key outside right top vertical box opaque\n";
    if (plot.equal_axes) gp << "set size ratio -1\n";
    gp << "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n";  // markers off the border
    int arrow = 1;
    for (const PlotMarker& m : plot.markers) {
      if (m.arrow_length > 0.0) {
        gp << "set arrow " << arrow++ << " from " << m.x << "," << m.y << " rto "
           << m.arrow_length * std::cos(m.heading) << "," << m.arrow_length * std::sin(m.heading)
           << " lw 2 lc rgb " << quoted(m.color) << " front\n";
      }
    }
    gp << "plot " << quoted(plot.csv_path) << " using ($" << plot.x_column << "*" << plot.scale << "):($"
       << plot.y_column << "*" << plot.scale << ") with dots lc rgb '#3060c0' title " << quoted(plot.points_label);
    // Dots are one pixel: a second pass with tiny points gives the legend a visible symbol and the cloud density.
    gp << ", '' using ($" << plot.x_column << "*" << plot.scale << "):($" << plot.y_column << "*"
       << plot.scale << ") with points pt 7 ps 0.25 lc rgb '#3060c0' notitle";
    for (const PlotSegment& s : plot.segments) {
      gp << ", '-' with lines lw 3 lc rgb " << quoted(s.color) << " title " << quoted(s.label);
    }
    for (const PlotMarker& m : plot.markers) {
      gp << ", '-' with points pt " << m.point_type << " ps 2.2 lc rgb " << quoted(m.color) << " title "
         << quoted(m.label);
    }
    gp << "\n";
    // Inline blocks get a header line too: columnheaders applies to them as well.
    for (const PlotSegment& s : plot.segments)
      gp << "x,y\n" << s.x0 << "," << s.y0 << "\n" << s.x1 << "," << s.y1 << "\ne\n";
    for (const PlotMarker& m : plot.markers) gp << "x,y\n" << m.x << "," << m.y << "\ne\n";
    if (!gp) throw std::runtime_error("error writing gnuplot script " + script.string());
  }
  std::error_code ec;
  fs::remove(png, ec);
  const int rc = run_program({"gnuplot", script.string()});
  if (rc != 0)
    throw std::runtime_error("gnuplot " + script.string() + " failed (exit " + std::to_string(rc) +
                             "); is gnuplot installed (scripts/setup)?");
  if (!fs::exists(png) || fs::file_size(png) == 0) throw std::runtime_error("gnuplot wrote no " + png.string());
}

void run_gnuplot(const std::filesystem::path& script, const std::filesystem::path& png) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::remove(png, ec);
  // The scripts name their data files relative to their folder, so they also run by hand there.
  const int rc = run_program({"sh", "-c", "cd \"$1\" && exec gnuplot \"$2\"", "sh",
                              script.parent_path().string(), script.filename().string()});
  if (rc != 0)
    throw std::runtime_error("gnuplot " + script.string() + " failed (exit " + std::to_string(rc) +
                             "); is gnuplot installed (scripts/setup)?");
  if (!fs::exists(png) || fs::file_size(png) == 0) throw std::runtime_error("gnuplot wrote no " + png.string());
}


}  // namespace sim

#pragma once
// Plots for the host tools: a gnuplot script is generated next to the PNG and gnuplot (pngcairo) is run on it as a
// subprocess. Host only; errors are thrown as std::runtime_error with the command and what went wrong.
#include <filesystem>
#include <string>
#include <vector>

namespace sim {

// A point drawn on top of the data, with a legend entry.
struct PlotMarker {
  double x = 0.0;
  double y = 0.0;
  std::string label;
  int point_type = 7;          // gnuplot pointtype (7 filled circle, 5 filled square, 9 filled triangle, 2 cross)
  std::string color = "black";
  double heading = 0.0;        // rad; an arrow of arrow_length is drawn along it when arrow_length > 0
  double arrow_length = 0.0;   // in plot units
};

// A line segment (e.g. the robot's frame at the start).
struct PlotSegment {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  std::string label;
  std::string color = "gray40";
};

// A scatter plot of two columns of a CSV file with a one-line header, each scaled (e.g. metres to centimetres).
struct ScatterPlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::string csv_path;
  int x_column = 1;  // 1-based, as gnuplot counts
  int y_column = 2;
  double scale = 1.0;
  std::string points_label = "samples";
  std::vector<PlotMarker> markers;
  std::vector<PlotSegment> segments;
  bool equal_axes = true;
  int width_px = 1200;
  int height_px = 800;
};

// Writes <png_path without .png>.gp and runs gnuplot on it; throws if gnuplot is missing or fails, or no PNG appears.
void render_scatter_png(const ScatterPlot& plot, const std::string& png_path);

// Runs gnuplot on `script` in the script's folder (its data files are named relative to it, so it also runs by hand
// there); throws if gnuplot fails or `png` is not written.
void run_gnuplot(const std::filesystem::path& script, const std::filesystem::path& png);

// Runs a program with arguments (no shell), returns its exit status (-1 if it could not be started).
int run_program(const std::vector<std::string>& argv);

}  // namespace sim

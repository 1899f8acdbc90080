// sim_host import mrclam (data/mrclam.hpp).
#include "data/mrclam.hpp"

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/landmark_sighting_t.hpp>
#include <est_lcm/twist_t.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include "data/channels.hpp"
#include "data/event_buffer.hpp"
#include "data/formats.hpp"
#include "data/eval_report.hpp"
#include "data/line_reader.hpp"
#include "hal/lcm/lcm_log_reader.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

constexpr double kSampledStepS = 0.02;  // sampled-50hz/: row k of ground truth and odometry is at t = 0.02 k

using Rows = NumericRows;

// What a row may hold, so that the log can carry it (nanosecond stamps, floats) and the arena map stays small; the
// datasets stay far inside (times 1.25e9 s raw, 0 .. 2500 s sampled; the arena within 10 m; speeds under 1 m/s).
constexpr double kMaxTime = 9e9;         // s: nanosecond stamps fit an int64 to 9.2e9 s (the year 2262)
constexpr double kMaxPosition = 100.0;   // m from the origin, landmarks and ground truth
constexpr double kMaxSpeed = 100.0;      // m/s and rad/s, odometry
constexpr double kMaxRange = 1000.0;     // m, measurements
constexpr double kMaxAngle = 100.0;      // rad, headings and bearings (any turn count a float keeps to the degree)
constexpr double kMaxSubject = 1000.0;   // subjects 1 .. 1000, barcodes 0 .. 1000

bool whole_in(double v, double lo, double hi) { return v >= lo && v <= hi && v == std::floor(v); }

// Drops the rows `why` names a reason for (a bad line: skipped and counted, or the import refused).
template <class Why>
void keep_rows(Rows& rows, ImportReport& report, const Why& why) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < rows.values.size(); ++k) {
    if (const char* reason = why(rows.values[k])) {
      report.bad_line(rows.path, rows.lines[k], reason);
      continue;
    }
    if (kept != k) {  // (a vector moved onto itself is left empty)
      rows.values[kept] = std::move(rows.values[k]);
      rows.lines[kept] = rows.lines[k];
    }
    ++kept;
  }
  rows.values.resize(kept);
  rows.lines.resize(kept);
}
const char* time_reason(const std::vector<double>& v) {
  return v[0] >= 0.0 && v[0] <= kMaxTime ? nullptr : "time outside 0 .. 9e9 s";
}


Rows read_rows(const std::string& path, std::size_t fields, ImportReport& report) {
  return read_numeric_rows(path, fields, report);
}

bool has_header(const std::string& path) {
  LineReader in(path);
  std::string line;
  return in.next(line) && blank_or_comment(line);
}

struct Feature {
  int id;
  float range, bearing, signature;
};

est_lcm::landmark_sighting_t sighting(std::int64_t t_ns, const std::vector<Feature>& fs) {
  est_lcm::landmark_sighting_t m;
  m.stamp_ns = t_ns;
  m.num_features = static_cast<std::int16_t>(fs.size());
  for (const Feature& f : fs) {
    m.range_m.push_back(f.range);
    m.bearing_rad.push_back(f.bearing);
    m.signature.push_back(f.signature);
    m.id.push_back(f.id);
  }
  return m;
}

// The free arena around the landmarks (margin m on every side, a wall of one cell around it): MCL's map, whose
// free space bounds the particles and where recovery draws from.
std::string write_arena_map(const std::string& stem, const std::vector<MrclamLandmark>& lms, double margin) {
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const MrclamLandmark& l : lms) {
    x0 = std::min(x0, l.x), y0 = std::min(y0, l.y), x1 = std::max(x1, l.x), y1 = std::max(y1, l.y);
  }
  const double res = 0.05;
  x0 -= margin, y0 -= margin, x1 += margin, y1 += margin;
  const int w = static_cast<int>(std::ceil((x1 - x0) / res)) + 2;
  const int h = static_cast<int>(std::ceil((y1 - y0) / res)) + 2;
  const std::string pgm = stem + ".arena.pgm";
  const std::string yaml = stem + ".arena.yaml";
  std::ofstream p(pgm, std::ios::binary);
  p << "P5\n" << w << " " << h << "\n255\n";
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) p.put(r == 0 || c == 0 || r == h - 1 || c == w - 1 ? char(0) : char(254));
  std::ofstream y(yaml);
  y << "image: " << fs::path(pgm).filename().string() << "\nresolution: " << res << "\norigin: [" << x0 - res << ", "
    << y0 - res << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  if (!p || !y) throw std::runtime_error(stem + ": cannot write the arena map");
  return yaml;
}

}  // namespace

MrclamImport import_mrclam(const std::string& dir, const std::string& out_log, const MrclamImportOptions& o,
                           ImportReport& report) {
  MrclamImport result;
  const auto file = [&](const std::string& name) {
    const std::string p = (fs::path(dir) / name).string();
    if (!fs::exists(p)) throw std::runtime_error(dir + ": not an MRCLAM dataset folder (" + name + " missing)");
    return p;
  };
  const std::string folder = fs::path(dir).lexically_normal().filename().string().empty()
                                 ? fs::path(dir).lexically_normal().parent_path().filename().string()
                                 : fs::path(dir).lexically_normal().filename().string();
  const std::string tag = "Dataset";  // the folder's name ends in Dataset1 .. Dataset9
  if (folder.size() > tag.size() && folder.compare(folder.size() - tag.size() - 1, tag.size(), tag) == 0 &&
      folder.back() >= '1' && folder.back() <= '9')
    result.dataset = folder.back() - '0';
  result.sampled = !has_header(file("Robot1_Odometry.dat"));

  // Barcodes: the measurement files name barcodes; subjects 1-5 are the robots, 6-20 the landmarks.
  std::map<int, int> subject_of_barcode;
  Rows barcodes = read_rows(file("Barcodes.dat"), 2, report);
  keep_rows(barcodes, report, [](const std::vector<double>& v) -> const char* {
    return whole_in(v[0], 1.0, kMaxSubject) && whole_in(v[1], 0.0, kMaxSubject)
               ? nullptr
               : "subject and barcode must be whole numbers in 1 .. 1000 and 0 .. 1000";
  });
  for (const auto& v : barcodes.values) subject_of_barcode[static_cast<int>(v[1])] = static_cast<int>(v[0]);
  Rows landmarks = read_rows(file("Landmark_Groundtruth.dat"), 5, report);
  keep_rows(landmarks, report, [](const std::vector<double>& v) -> const char* {
    if (!whole_in(v[0], 1.0, kMaxSubject)) return "subject must be a whole number in 1 .. 1000";
    return std::fabs(v[1]) <= kMaxPosition && std::fabs(v[2]) <= kMaxPosition ? nullptr
                                                                                : "landmark beyond 100 m of the origin";
  });
  for (const auto& v : landmarks.values) result.landmarks.push_back({static_cast<int>(v[0]), v[1], v[2]});
  if (result.landmarks.empty()) throw std::runtime_error(dir + ": no landmarks in Landmark_Groundtruth.dat");
  if (result.dataset == 1 && o.fix_landmarks) {
    auto find = [&](int s) {
      return std::find_if(result.landmarks.begin(), result.landmarks.end(),
                          [s](const MrclamLandmark& l) { return l.subject == s; });
    };
    const auto a = find(11), b = find(17);
    if (a != result.landmarks.end() && b != result.landmarks.end()) {
      std::swap(a->x, b->x);
      std::swap(a->y, b->y);
      report.note("MRCLAM Dataset 1: Landmark_Groundtruth.dat has subjects 11 and 17 swapped (the observations put "
                  "11 near (0.02, -2.83) and 17 near (3.15, 2.38), 6.1 m from the file); swapped back "
                  "(--keep-landmark-file to import the file as it is)");
    }
  }
  std::map<int, int> landmark_index;
  for (std::size_t i = 0; i < result.landmarks.size(); ++i) landmark_index[result.landmarks[i].subject] = int(i);

  // Every file of the robots, then the time origin: the earliest time of any of them (raw/), t = 0 (sampled/).
  struct RobotFiles {
    int subject;
    Rows odometry, measurements, truth;
  };
  std::vector<RobotFiles> robots;
  for (int s : o.robots) {
    if (s < 1 || s > kMrclamRobots) throw std::invalid_argument("MRCLAM robots are subjects 1..5");
    RobotFiles r{s, read_rows(file("Robot" + std::to_string(s) + "_Odometry.dat"), 3, report),
                 read_rows(file("Robot" + std::to_string(s) + "_Measurement.dat"), 4, report), {}};
    const std::string gt = (fs::path(dir) / ("Robot" + std::to_string(s) + "_Groundtruth.dat")).string();
    if (fs::exists(gt)) r.truth = read_rows(gt, 4, report);
    // Times the log can stamp (the sampled layout times ground truth and odometry by their row, not the column).
    // Each file in time order (a row before the previous one is a bad line), so that no row comes before the time
    // origin, the earliest first row.
    const auto times = [&](Rows& rows) {
      keep_rows(rows, report, time_reason);
      double last = 0.0;
      keep_rows(rows, report, [&last](const std::vector<double>& v) -> const char* {
        if (v[0] < last) return "time before the previous row's";
        last = v[0];
        return nullptr;
      });
    };
    if (!result.sampled) times(r.odometry);
    if (!result.sampled) times(r.truth);
    times(r.measurements);
    keep_rows(r.truth, report, [](const std::vector<double>& v) -> const char* {
      return std::fabs(v[1]) <= kMaxPosition && std::fabs(v[2]) <= kMaxPosition && std::fabs(v[3]) <= kMaxAngle
                 ? nullptr
                 : "pose beyond 100 m of the origin or a heading beyond 100 rad";
    });
    keep_rows(r.odometry, report, [](const std::vector<double>& v) -> const char* {
      return std::fabs(v[1]) <= kMaxSpeed && std::fabs(v[2]) <= kMaxSpeed ? nullptr
                                                                            : "speed beyond 100 m/s or 100 rad/s";
    });
    keep_rows(r.measurements, report, [](const std::vector<double>& v) -> const char* {
      if (!whole_in(v[1], 0.0, kMaxSubject)) return "barcode must be a whole number in 0 .. 1000";
      if (!(v[2] > 0.0 && v[2] <= kMaxRange)) return "range not in (0, 1000] m";
      return std::fabs(v[3]) <= kMaxAngle ? nullptr : "bearing beyond 100 rad";
    });
    robots.push_back(std::move(r));
  }
  result.has_ground_truth = std::all_of(robots.begin(), robots.end(), [](const RobotFiles& r) {
    return !r.truth.values.empty();
  });
  if (!result.has_ground_truth)
    report.note("no robot ground truth in " + dir + " (raw/ of Datasets 1 and 2 lacks it): the log has none");
  if (!result.sampled) {
    double t0 = std::numeric_limits<double>::infinity();
    for (const RobotFiles& r : robots)
      for (const Rows* rows : {&r.odometry, &r.measurements, &r.truth})
        if (!rows->values.empty()) t0 = std::min(t0, rows->values.front()[0]);
    result.t0_unix_s = std::isfinite(t0) ? t0 : 0.0;
  } else {
    report.note("sampled-50hz layout: ground truth and odometry timed by their row (t = 0.02 k); measurement times "
                "as printed (5 significant digits: 0.1 s resolution after t = 1000 s)");
  }
  for (int s : o.robots)
    if (o.scale_v[s] != 1.0 || o.scale_w[s] != 1.0 || o.lag_s[s] != 0.0)
      report.note("robot " + std::to_string(s) + ": the commanded (v, w) scaled by (" + fixed(o.scale_v[s], 3) + ", " +
                  fixed(o.scale_w[s], 3) + ") and delayed by " + fixed(o.lag_s[s], 2) + " s, an odometry calibration");
  const auto stamp = [&](double t) { return static_cast<std::int64_t>(std::llround((t - result.t0_unix_s) * 1e9)); };
  const double t_end = o.max_seconds > 0.0 ? o.max_seconds : std::numeric_limits<double>::infinity();

  EventBuffer events;  // order at equal stamps: ground truth 0, twists 1, landmark 2 and robot 3 sightings
  for (const RobotFiles& r : robots) {
    const int s = r.subject;
    const std::string ch_twist = robot_channel("EST_TWIST", s), ch_lm = robot_channel("EST_LANDMARKS", s);
    const std::string ch_rb = robot_channel(kRobotSightingsChannel, s), ch_gt = robot_channel(kGroundTruthChannel, s);
    for (std::size_t k = 0; k < r.truth.values.size(); ++k) {
      const auto& v = r.truth.values[k];
      const double t = result.sampled ? kSampledStepS * static_cast<double>(k) : v[0];
      if (t - result.t0_unix_s > t_end) break;
      est_lcm::ground_truth_t g;
      g.stamp_ns = stamp(t);
      g.x_m = static_cast<float>(v[1]);
      g.y_m = static_cast<float>(v[2]);
      g.theta_rad = static_cast<float>(v[3]);
      if (k == 0) std::copy(v.begin() + 1, v.begin() + 4, result.start[s]);
      g.v_mps = 0.0f;
      g.omega_rps = 0.0f;
      events.add(g.stamp_ns, 0, ch_gt, g);
    }
    report.count("ground-truth poses", r.truth.values.size());
    for (std::size_t k = 0; k < r.odometry.values.size(); ++k) {
      const auto& v = r.odometry.values[k];
      const double t = (result.sampled ? kSampledStepS * static_cast<double>(k) : v[0]) + o.lag_s[s];
      if (t - result.t0_unix_s > t_end) break;
      est_lcm::twist_t tw;
      tw.stamp_ns = stamp(t);
      tw.v1_mps = static_cast<float>(v[1] * o.scale_v[s]);
      tw.v2_mps = 0.0f;
      tw.w_rps = static_cast<float>(v[2] * o.scale_w[s]);
      events.add(tw.stamp_ns, 1, ch_twist, tw);
      report.count("odometry (v, w)");
    }
    // Measurements: the rows of one time become one sighting per kind (landmarks, robots).
    std::vector<Feature> lms, rbs;
    std::int64_t group_t = 0;
    const auto flush = [&] {
      if (!lms.empty()) events.add(group_t, 2, ch_lm, sighting(group_t, lms));
      if (!rbs.empty()) events.add(group_t, 3, ch_rb, sighting(group_t, rbs));
      lms.clear();
      rbs.clear();
    };
    for (std::size_t k = 0; k < r.measurements.values.size(); ++k) {
      const auto& v = r.measurements.values[k];
      if (v[0] - result.t0_unix_s > t_end) break;
      const std::int64_t t = stamp(v[0]);
      if (t != group_t) flush();
      group_t = t;
      const auto it = subject_of_barcode.find(static_cast<int>(v[1]));  // a whole number (keep_rows)
      if (it == subject_of_barcode.end()) {
        report.count("measurements of barcodes not in Barcodes.dat (dropped)");
        continue;
      }
      const int subject = it->second;
      const Feature f{0, static_cast<float>(v[2]), static_cast<float>(v[3]), static_cast<float>(subject)};
      if (subject >= 1 && subject <= kMrclamRobots) {
        rbs.push_back({subject, f.range, f.bearing, f.signature});
        report.count("robot sightings");
      } else if (const auto li = landmark_index.find(subject); li != landmark_index.end()) {
        lms.push_back({li->second, f.range, f.bearing, f.signature});
        report.count("landmark sightings");
      } else {
        report.count("measurements of subjects with no landmark position (dropped)");
      }
    }
    flush();
  }
  result.duration_s = static_cast<double>(events.last_ns()) * 1e-9;
  result.events = events.write_sorted(out_log);

  const std::string stem = out_log.size() > 7 && out_log.compare(out_log.size() - 7, 7, ".lcmlog") == 0
                               ? out_log.substr(0, out_log.size() - 7)
                               : out_log;
  result.landmarks_csv = stem + ".landmarks.csv";
  std::ofstream csv(result.landmarks_csv);
  csv << "# MRCLAM landmarks: x [m], y [m], signature (the subject number); the line order is the map index\n";
  char buf[96];
  for (const MrclamLandmark& l : result.landmarks) {
    std::snprintf(buf, sizeof buf, "%.6f,%.6f,%d\n", l.x, l.y, l.subject);
    csv << buf;
  }
  if (!csv) throw std::runtime_error(result.landmarks_csv + ": cannot write");
  result.arena_yaml = write_arena_map(stem, result.landmarks, 1.5);
  return result;
}

std::vector<MrclamRobotLog> read_mrclam_log(const std::string& path, const std::vector<int>& subjects) {
  std::vector<MrclamRobotLog> out;
  std::map<std::string, std::pair<std::size_t, int>> channel;  // channel -> (robot, kind)
  for (int s : subjects) {
    out.push_back({s, {}, {}, {}, {}});
    channel[robot_channel(kGroundTruthChannel, s)] = {out.size() - 1, 0};
    channel[robot_channel("EST_TWIST", s)] = {out.size() - 1, 1};
    channel[robot_channel("EST_LANDMARKS", s)] = {out.size() - 1, 2};
    channel[robot_channel(kRobotSightingsChannel, s)] = {out.size() - 1, 3};
  }
  hal::lcm::read_lcm_log(path, "sim_host: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    const auto it = channel.find(e.channel);
    if (it == channel.end()) return;
    MrclamRobotLog& r = out[it->second.first];
    switch (it->second.second) {
      case 0: {
        est_lcm::ground_truth_t g;
        if (g.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad ground_truth_t");
        r.truth.push_back({g.stamp_ns, g.x_m, g.y_m, g.theta_rad});
        break;
      }
      case 1: {
        est_lcm::twist_t t;
        if (t.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad twist_t");
        r.twists.push_back({t.stamp_ns, t.v1_mps, t.w_rps});
        break;
      }
      default: {
        est_lcm::landmark_sighting_t m;
        if (m.decode(e.data.data(), 0, e.size()) < 0) throw std::runtime_error(path + ": bad landmark_sighting_t");
        auto& list = it->second.second == 2 ? r.landmarks : r.robots;
        for (std::size_t i = 0; i < static_cast<std::size_t>(m.num_features); ++i)
          list.push_back({m.stamp_ns, m.id[i], m.range_m[i], m.bearing_rad[i]});
      }
    }
  });
  return out;
}

MrclamOdometryScales fit_mrclam_odometry_scales(const std::string& dir, double window_s) {
  MrclamOdometryScales out;
  ImportReport quiet(OnError::skip, nullptr);
  if (has_header((fs::path(dir) / "Robot1_Odometry.dat").string()))
    throw std::runtime_error(dir + ": the odometry calibration needs the sampled-50hz layout (rows on one grid)");
  // Windows of 2 s by default (why: the header); the distance is summed over 0.5 s chords, arcs to well under a
  // millimetre at these speeds.
  constexpr std::size_t kChord = 25;    // 0.5 s, in rows
  const long chords = std::lround(window_s / (kSampledStepS * static_cast<double>(kChord)));
  if (chords < 1 || chords > 40)
    throw std::invalid_argument("the odometry calibration's window must be 0.5 to 20 s in steps of 0.5 s");
  const std::size_t window_rows = static_cast<std::size_t>(chords) * kChord;
  constexpr std::size_t kMaxLag = 25;   // 0.5 s, in rows
  for (int s = 1; s <= kMrclamRobots; ++s) {
    const std::string id = std::to_string(s);
    const Rows gt = read_rows((fs::path(dir) / ("Robot" + id + "_Groundtruth.dat")).string(), 4, quiet);
    const Rows od = read_rows((fs::path(dir) / ("Robot" + id + "_Odometry.dat")).string(), 3, quiet);
    const std::size_t n = std::min(gt.values.size(), od.values.size());
    double best_residual = std::numeric_limits<double>::infinity();
    for (std::size_t lag = 0; lag <= kMaxLag; ++lag) {
      // The true increment over rows [k, k + window_rows) against the commands of the rows `lag` earlier.
      double sw = 0.0, sww = 0.0, stt = 0.0, sv = 0.0, svv = 0.0;
      for (std::size_t k = kMaxLag; k + window_rows < n; k += window_rows) {
        const auto& a = gt.values[k];
        const auto& b = gt.values[k + window_rows];
        const double dtheta = wrap_angle(b[3] - a[3]);  // |turn| < pi in 2 s at the robots' rates
        double ds = 0.0;
        for (std::size_t c = k; c < k + window_rows; c += kChord)
          ds += std::hypot(gt.values[c + kChord][1] - gt.values[c][1], gt.values[c + kChord][2] - gt.values[c][2]);
        double cv = 0.0, cw = 0.0;
        for (std::size_t j = k - lag; j < k + window_rows - lag; ++j) {
          cv += od.values[j][1] * kSampledStepS;
          cw += od.values[j][2] * kSampledStepS;
        }
        sw += dtheta * cw, sww += cw * cw, stt += dtheta * dtheta, sv += ds * std::fabs(cv), svv += cv * cv;
      }
      if (!(sww > 0.0)) break;
      const double residual = stt - sw * sw / sww;  // of the least squares turn fit
      if (residual < best_residual) {
        best_residual = residual;
        out.lag_s[s] = kSampledStepS * static_cast<double>(lag);
        out.w[s] = sw / sww;
        out.v[s] = svv > 0.0 ? sv / svv : 1.0;
      }
    }
  }
  return out;
}

}  // namespace sim::data

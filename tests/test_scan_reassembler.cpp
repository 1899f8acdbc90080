// Scan reassembly: a scan split into frames comes back exactly (to the millimetre); every way the frames can go
// wrong is rejected with its reason counted, and the next good scan still comes through.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/range_scan/can_reassembler.hpp"

using namespace hal::can;
using hal::kNsPerMs;
using hal::TimeNs;

namespace {

struct Scan {
  std::vector<float> ranges;
  hal::ScanGeometry geometry{-2.35619f, 0.00436332f, 0.06f, 30.0f, 0.025f};
  hal::RangeScanView view(TimeNs stamp = 0) const { return {stamp, geometry, ranges.data(), ranges.size()}; }
};

Scan make_scan(std::size_t n) {
  Scan s;
  for (std::size_t i = 0; i < n; ++i) s.ranges.push_back(0.5f + 0.01f * static_cast<float>(i));
  return s;
}

std::vector<CanFrame> frames_of(const Scan& s, std::uint8_t id) {
  std::vector<CanFrame> f(scan_frame_count(s.ranges.size()));
  const ScanSplit split = split_scan(s.view(), id, f.data(), f.size());
  REQUIRE(split.status == CodecStatus::ok);
  REQUIRE(split.frames == f.size());
  return f;
}

template <std::size_t K>
int feed(ScanReassembler<K>& r, const std::vector<CanFrame>& frames, TimeNs t0 = 0, TimeNs step = 100000) {
  int complete = 0;
  TimeNs t = t0;
  for (const CanFrame& f : frames) {
    if (r.on_frame(f, t).complete) ++complete;
    t += step;
  }
  return complete;
}

template <std::size_t K>
void check_recovers(ScanReassembler<K>& r, std::uint8_t id) {
  const Scan good = make_scan(12);
  INFO("a good scan after the fault");
  CHECK(feed(r, frames_of(good, id), 10 * hal::kNsPerS) == 1);
}

}  // namespace

TEST_CASE("a 1081-beam scan comes back to the millimetre with its geometry and header stamp", "[can][scan]") {
  Scan s = make_scan(1081);
  s.ranges[5] = std::numeric_limits<float>::infinity();
  s.ranges[6] = 65.6f;  // beyond the bus's range: no return
  s.ranges[7] = std::numeric_limits<float>::quiet_NaN();
  const auto frames = frames_of(s, 4);
  CHECK(frames.size() == 2 + 361);
  ScanReassembler<1081> r;
  REQUIRE(feed(r, frames, 5000) == 1);
  const hal::RangeScanView v = r.scan();
  CHECK(v.stamp_ns == 5000);
  REQUIRE(v.count == 1081);
  for (std::size_t i = 0; i < v.count; ++i) {
    if (i >= 5 && i <= 7) continue;
    INFO("beam " << i);
    CHECK(std::abs(v.ranges[i] - s.ranges[i]) <= 0.0005f + 1e-6f);
  }
  CHECK(std::isinf(v.ranges[5]));
  CHECK(std::isinf(v.ranges[6]));
  CHECK(v.ranges[7] == 0.0f);  // NaN travels as 0: below any range_min, so unusable
  CHECK(v.geometry.angle_min_rad == Approx(-2.3562).margin(1e-7));
  CHECK(v.geometry.angle_increment_rad == Approx(0.00436332).margin(1e-9));
  CHECK(v.geometry.range_min_m == Approx(0.06).margin(1e-6));
  CHECK(v.geometry.range_max_m == Approx(30.0).margin(1e-5));
  CHECK(v.geometry.scan_time_s == Approx(0.025).margin(1e-6));
  CHECK(r.rejects().total() == 0);
  CHECK(r.scans_completed() == 1);
}

TEST_CASE("a lost data frame is a sequence gap and the rest of that scan is dropped", "[can][scan]") {
  ScanReassembler<100> r;
  auto frames = frames_of(make_scan(30), 1);
  frames.erase(frames.begin() + 5);
  CHECK(feed(r, frames) == 0);
  CHECK(r.rejects()[ScanReject::sequence_gap] == 1);
  CHECK(r.rejects().total() == 1);
  CHECK(r.frames_dropped() == frames.size() - 5 - 1);
  check_recovers(r, 2);
}

TEST_CASE("a lost SCAN_INFO is a sequence gap", "[can][scan]") {
  ScanReassembler<100> r;
  auto frames = frames_of(make_scan(30), 1);
  frames.erase(frames.begin() + 1);
  CHECK(feed(r, frames) == 0);
  CHECK(r.rejects()[ScanReject::sequence_gap] == 1);
  check_recovers(r, 2);
}

TEST_CASE("a corrupted range is a bad checksum", "[can][scan]") {
  ScanReassembler<100> r;
  auto frames = frames_of(make_scan(30), 1);
  frames[4].data[3] ^= 0x01;
  CHECK(feed(r, frames) == 0);
  CHECK(r.rejects()[ScanReject::bad_checksum] == 1);
  // The geometry is covered too.
  frames = frames_of(make_scan(30), 3);
  frames[1].data[2] ^= 0x80;
  CHECK(feed(r, frames, hal::kNsPerS) == 0);
  CHECK(r.rejects()[ScanReject::bad_checksum] == 2);
  check_recovers(r, 2);
}

TEST_CASE("duplicated frames are counted and dropped, and the scan completes", "[can][scan]") {
  ScanReassembler<100> r;
  auto frames = frames_of(make_scan(30), 1);
  std::vector<CanFrame> with_dups;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    with_dups.push_back(frames[i]);
    if (i == 0 || i == 1 || i == 3) with_dups.push_back(frames[i]);
  }
  with_dups.push_back(frames.back());  // after completion too
  CHECK(feed(r, with_dups) == 1);
  CHECK(r.rejects()[ScanReject::duplicate_frame] == 4);
  CHECK(r.rejects().total() == 4);
}

TEST_CASE("frames of another scan in the middle of a scan are interleaved", "[can][scan]") {
  ScanReassembler<100> r;
  auto a = frames_of(make_scan(30), 1);
  auto b = frames_of(make_scan(30), 2);
  std::vector<CanFrame> mixed(a.begin(), a.begin() + 4);
  mixed.push_back(b[3]);
  mixed.insert(mixed.end(), a.begin() + 4, a.end());
  CHECK(feed(r, mixed) == 0);
  CHECK(r.rejects()[ScanReject::interleaved] == 1);
  CHECK(r.rejects().total() == 1);
  check_recovers(r, 5);
}

TEST_CASE("a new header before the scan is complete truncates it; the new scan goes on", "[can][scan]") {
  ScanReassembler<100> r;
  auto a = frames_of(make_scan(30), 1);
  auto b = frames_of(make_scan(12), 2);
  std::vector<CanFrame> cut(a.begin(), a.begin() + 6);
  cut.insert(cut.end(), b.begin(), b.end());
  CHECK(feed(r, cut) == 1);
  CHECK(r.rejects()[ScanReject::truncated] == 1);
  CHECK(r.scan().count == 12);
}

TEST_CASE("frames without their header are orphans", "[can][scan]") {
  ScanReassembler<100> r;
  auto a = frames_of(make_scan(30), 1);
  std::vector<CanFrame> headless(a.begin() + 1, a.end());
  CHECK(feed(r, headless) == 0);
  CHECK(r.rejects()[ScanReject::orphan_frame] == headless.size());
  check_recovers(r, 2);
}

TEST_CASE("a burst: more frames than announced, or more beams than the reassembler holds", "[can][scan]") {
  ScanReassembler<16> r;
  auto small = frames_of(make_scan(6), 1);  // 2 data frames announced
  CanFrame extra = small[3];
  extra.data[0] = static_cast<std::uint8_t>((extra.data[0] & 0x0F) | (5u << 4));  // Seq 5
  std::vector<CanFrame> burst = {small[0], small[1], small[2], extra, small[3]};
  CHECK(feed(r, burst) == 0);
  CHECK(r.rejects()[ScanReject::extra_frame] == 1);

  auto big = frames_of(make_scan(100), 3);  // 100 beams > 16
  CHECK(feed(r, big, hal::kNsPerS) == 0);
  CHECK(r.rejects()[ScanReject::exceeds_capacity] == 1);
  CHECK(r.rejects().total() == 2);
  CHECK(r.frames_dropped() >= big.size() - 1);  // the whole burst is dropped, not counted frame by frame
  check_recovers(r, 4);
}

TEST_CASE("a scan that stalls times out, by poll or by a late frame", "[can][scan]") {
  ScanReassembler<100> r(50 * kNsPerMs);
  auto a = frames_of(make_scan(30), 1);
  std::vector<CanFrame> half(a.begin(), a.begin() + 5);
  CHECK(feed(r, half) == 0);
  CHECK(r.poll(40 * kNsPerMs) == ScanReject::none);
  CHECK(r.poll(51 * kNsPerMs) == ScanReject::timeout);
  CHECK(r.rejects()[ScanReject::timeout] == 1);

  auto b = frames_of(make_scan(30), 2);
  CHECK(feed(r, std::vector<CanFrame>(b.begin(), b.begin() + 5), hal::kNsPerS) == 0);
  CHECK(r.on_frame(b[5], hal::kNsPerS + 60 * kNsPerMs).reject == ScanReject::timeout);
  CHECK(r.rejects()[ScanReject::timeout] == 2);
  check_recovers(r, 3);
}

TEST_CASE("wrong DLC and an empty scan header are rejected", "[can][scan]") {
  ScanReassembler<100> r;
  auto a = frames_of(make_scan(30), 1);
  CanFrame short_frame = a[2];
  short_frame.dlc = 6;
  CHECK(r.on_frame(short_frame, 0).reject == ScanReject::wrong_dlc);
  CanFrame empty;
  REQUIRE(encode(ScanHeaderMsg{7, 0, 0xFFFF, 0.1f, 10.0f}, empty) == CodecStatus::ok);
  CHECK(r.on_frame(empty, 0).reject == ScanReject::bad_header);
  CHECK(r.rejects()[ScanReject::wrong_dlc] == 1);
  CHECK(r.rejects()[ScanReject::bad_header] == 1);
  check_recovers(r, 2);
}

TEST_CASE("split_scan refuses what the bus cannot carry", "[can][scan]") {
  std::vector<CanFrame> out(2000);
  Scan s = make_scan(4096);
  CHECK(split_scan(s.view(), 0, out.data(), out.size()).status == CodecStatus::out_of_range);
  s = make_scan(30);
  CHECK(split_scan(s.view(), 0, out.data(), 5).status == CodecStatus::out_of_range);  // no room
  s.geometry.range_min_m = 5.0f;  // RangeMin is 12 bits of millimetres
  CHECK(split_scan(s.view(), 0, out.data(), out.size()).status == CodecStatus::out_of_range);
}

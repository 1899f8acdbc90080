// libFuzzer target: scan reassembly. The input describes a scan and edits to its frames (drop, duplicate, swap,
// flip a bit, inject a foreign frame, jump the clock). Invariants: bounded state, no NaN ranges, the unedited scan
// always completes, and a scan that completes after edits without bit flips equals the original.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/range_scan/can_reassembler.hpp"

using namespace hal::can;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) return 0;
  const std::size_t count = 1 + data[0] % 80;  // up to 80 beams into a reassembler of 64: bursts included
  const auto scan_id = static_cast<std::uint8_t>(data[1] & 0x0F);
  std::vector<float> ranges(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t b = data[(2 + i) % size];
    ranges[i] = b == 255 ? __builtin_inff() : static_cast<float>(b) * 0.1f;
  }
  hal::RangeScanView v{0, {-1.0f, 0.02f, 0.05f, 25.0f, 0.1f}, ranges.data(), ranges.size()};
  std::vector<CanFrame> frames(scan_frame_count(count));
  if (split_scan(v, scan_id, frames.data(), frames.size()).status != CodecStatus::ok) __builtin_trap();
  const std::vector<CanFrame> original = frames;

  bool flipped = false;
  for (std::size_t i = 2; i + 2 < size && i < 2 + 3 * 64; i += 3) {
    const std::uint8_t op = data[i] % 7;
    if (frames.empty()) break;
    const std::size_t k = data[i + 1] % frames.size();
    switch (op) {
      case 0: frames.erase(frames.begin() + static_cast<std::ptrdiff_t>(k)); break;
      case 1: frames.insert(frames.begin() + static_cast<std::ptrdiff_t>(k), frames[k]); break;
      case 2: std::swap(frames[k], frames[data[i + 2] % frames.size()]); break;
      case 3:
        frames[k].data[data[i + 2] % 8] ^= static_cast<std::uint8_t>(1u << (data[i + 2] / 32));
        flipped = true;
        break;
      case 4: {
        CanFrame other = frames[k];
        other.data[0] = static_cast<std::uint8_t>((other.data[0] & 0xF0) | ((scan_id + 1) & 0x0F));
        frames.insert(frames.begin() + static_cast<std::ptrdiff_t>(k), other);
        flipped = true;  // a header of another scan id starts a different scan
        break;
      }
      case 5: frames[k].dlc = static_cast<std::uint8_t>(data[i + 2] % 9); break;
      default: break;  // op 6: the clock jumps before frame k (below)
    }
  }
  ScanReassembler<64> r(50 * hal::kNsPerMs);
  int completed = 0;
  hal::TimeNs t = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    t += (data[(k * 7) % size] == 0xEE) ? 60 * hal::kNsPerMs : 10000;
    const auto res = r.on_frame(frames[k], t);
    if (res.complete) {
      ++completed;
      const hal::RangeScanView s = r.scan();
      if (s.count == 0 || s.count > r.capacity()) __builtin_trap();
      for (std::size_t i = 0; i < s.count; ++i)
        if (s.ranges[i] != s.ranges[i]) __builtin_trap();
      if (!flipped && s.count == count) {
        for (std::size_t i = 0; i < count; ++i) {
          const float want = ranges[i];
          const float d = s.ranges[i] - want;
          if (!(s.ranges[i] == want || (d < 0.0006f && d > -0.0006f))) __builtin_trap();
        }
      }
    }
  }
  r.poll(t + hal::kNsPerS);
  // The unedited scan, after whatever happened, completes on a fresh reassembler with room for it.
  if (count <= 64) {
    ScanReassembler<64> fresh;
    int ok = 0;
    for (const CanFrame& f : original) ok += fresh.on_frame(f, 0).complete ? 1 : 0;
    if (ok != 1) __builtin_trap();
  }
  (void)completed;
  return 0;
}

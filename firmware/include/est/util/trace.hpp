#pragma once
// A workload's outputs, named: each one goes into a Digest (the same bits, in the same order, as Digest::add would
// take them) and, when a sink is attached, to the sink as a row (step, scope, name, index, value). The firmware does
// no I/O: the board runs with no sink and keeps only the digest; the host's sink writes golden-trace CSV
// (tests/support/golden_trace.hpp). The digest does not depend on the sink.
#include <cstdint>

#include "est/util/digest.hpp"

namespace est {

class TraceSink {
 public:
  // index: the entry of a matrix (column-major, as Digest::add_matrix), -1 for a scalar. Counts arrive as doubles
  // (every uint32 is exact in a double).
  virtual void row(std::uint32_t step, const char* scope, const char* name, std::int32_t index, double value) = 0;

 protected:
  ~TraceSink() = default;
};

class Trace {
 public:
  explicit Trace(TraceSink* sink = nullptr) : sink_(sink) {}

  // Outputs after this call belong to step k of the current scope (a model, a filter run).
  void step(std::uint32_t k) { step_ = k; }
  void scope(const char* s, std::uint32_t first_step = 0) {
    scope_ = s;
    step_ = first_step;
  }
  std::uint32_t current_step() const { return step_; }

  void add(const char* name, float v) {
    digest_.add(v);
    emit(name, -1, static_cast<double>(v));
  }
  void add_u32(const char* name, std::uint32_t v) {
    digest_.add_u32(v);
    emit(name, -1, static_cast<double>(v));
  }
  template <typename Matrix>
  void add_matrix(const char* name, const Matrix& m) {
    std::int32_t i = 0;
    for (int c = 0; c < static_cast<int>(m.cols()); ++c)
      for (int r = 0; r < static_cast<int>(m.rows()); ++r, ++i) {
        const float v = m(r, c);
        digest_.add(v);
        emit(name, i, static_cast<double>(v));
      }
  }

  std::uint64_t value() const { return digest_.value(); }

 private:
  void emit(const char* name, std::int32_t index, double v) {
    if (sink_ != nullptr) sink_->row(step_, scope_, name, index, v);
  }

  Digest digest_;
  TraceSink* sink_;
  const char* scope_ = "";
  std::uint32_t step_ = 0;
};

}  // namespace est

#pragma once
// What an import did, and what it refused: every malformed line is reported with its file and line number and either
// skipped (counted by reason) or refused (the import stops), as the user chose with --on-error; every correction
// applied to the data (a dataset's known fault) is said and kept. Nothing is dropped silently. Host only.
#include <cstdint>
#include <cstdio>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace sim::data {

enum class OnError { skip, refuse };
bool parse(const std::string& s, OnError& out);  // "skip", "refuse"

// A malformed line under --on-error refuse (what() names the file, the line and the reason).
struct ImportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ImportReport {
 public:
  explicit ImportReport(OnError mode = OnError::skip, std::FILE* diagnostics = stderr, int max_messages = 20);

  // A line that cannot be used: "file:line: reason" on the diagnostics stream (the first max_messages of them, then
  // only counted), counted under its reason; under OnError::refuse throws ImportError instead.
  void bad_line(const std::string& file, std::uint64_t line, const std::string& reason);
  // A correction of the data (e.g. MRCLAM Dataset 1's swapped landmarks): printed now, kept for the summary.
  void note(const std::string& message);
  // What was imported, by kind ("odometry", "landmark sightings", ...).
  void count(const std::string& what, std::uint64_t n = 1) { imported_[what] += n; }

  OnError mode() const { return mode_; }
  std::uint64_t skipped_total() const;
  const std::map<std::string, std::uint64_t>& skipped() const { return skipped_; }
  const std::map<std::string, std::uint64_t>& imported() const { return imported_; }
  const std::vector<std::string>& notes() const { return notes_; }

  // The summary: every count imported, every skipped line by reason, the notes.
  void print_summary(std::FILE* f, const std::string& title) const;
  nlohmann::json to_json() const;

 private:
  OnError mode_;
  std::FILE* diagnostics_;
  int max_messages_;
  int messages_ = 0;
  std::map<std::string, std::uint64_t> skipped_;
  std::map<std::string, std::uint64_t> imported_;
  std::vector<std::string> notes_;
};

}  // namespace sim::data

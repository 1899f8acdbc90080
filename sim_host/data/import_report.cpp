#include "data/import_report.hpp"

#include <nlohmann/json.hpp>

namespace sim::data {

bool parse(const std::string& s, OnError& out) {
  if (s == "skip") out = OnError::skip;
  else if (s == "refuse") out = OnError::refuse;
  else return false;
  return true;
}

ImportReport::ImportReport(OnError mode, std::FILE* diagnostics, int max_messages)
    : mode_(mode), diagnostics_(diagnostics), max_messages_(max_messages) {}

void ImportReport::bad_line(const std::string& file, std::uint64_t line, const std::string& reason) {
  const std::string where = file + ":" + std::to_string(line) + ": " + reason;
  if (mode_ == OnError::refuse) throw ImportError(where + " (refused: --on-error refuse)");
  ++skipped_[reason];
  if (diagnostics_ == nullptr) return;
  if (messages_ < max_messages_) std::fprintf(diagnostics_, "%s (skipped)\n", where.c_str());
  else if (messages_ == max_messages_)
    std::fprintf(diagnostics_, "... further malformed lines are only counted (see the summary)\n");
  ++messages_;
}

void ImportReport::note(const std::string& message) {
  notes_.push_back(message);
  if (diagnostics_ != nullptr) std::fprintf(diagnostics_, "note: %s\n", message.c_str());
}

std::uint64_t ImportReport::skipped_total() const {
  std::uint64_t n = 0;
  for (const auto& [reason, count] : skipped_) n += count;
  return n;
}

void ImportReport::print_summary(std::FILE* f, const std::string& title) const {
  std::fprintf(f, "%s\n  imported:\n", title.c_str());
  for (const auto& [what, n] : imported_)
    std::fprintf(f, "    %-34s %llu\n", what.c_str(), static_cast<unsigned long long>(n));
  std::fprintf(f, "  skipped lines: %llu\n", static_cast<unsigned long long>(skipped_total()));
  for (const auto& [reason, n] : skipped_)
    std::fprintf(f, "    %-34s %llu\n", reason.c_str(), static_cast<unsigned long long>(n));
  for (const std::string& n : notes_) std::fprintf(f, "  note: %s\n", n.c_str());
}

nlohmann::json ImportReport::to_json() const {
  return {{"imported", imported_}, {"skipped", skipped_}, {"skipped_total", skipped_total()}, {"notes", notes_}};
}

}  // namespace sim::data

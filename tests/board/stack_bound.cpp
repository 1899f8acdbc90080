#include "stack_bound.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace stackbound {
namespace {

bool is_leaf_helper(const std::string& title) {
  return title == "memcpy" || title == "memset" || title == "memmove" || title == "sqrtf" ||
         title.rfind("__aeabi_", 0) == 0;
}

}  // namespace

void add_ci(CallGraph& g, const std::string& text, const std::string& file) {
  static const std::regex node(R"re(^node: \{ title: "([^"]+)" label: "([^"]*)")re");
  static const std::regex frame(R"re(\\n([0-9]+) bytes \(([a-z,]+)\)$)re");
  static const std::regex edge(R"re(^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)")re");
  std::istringstream in(text);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    std::smatch m;
    if (std::regex_search(line, m, node)) {
      Function& f = g.functions[m[1]];
      const std::string label = m[2];
      f.name = label.substr(0, label.find("\\n"));
      std::smatch b;
      if (std::regex_search(label, b, frame)) {
        const std::uint32_t bytes = static_cast<std::uint32_t>(std::stoul(b[1]));
        f.frame = f.has_frame ? std::max(f.frame, bytes) : bytes;
        f.has_frame = true;
        const std::string q = b[2];
        if (q.find("dynamic") != std::string::npos && q.find("bounded") == std::string::npos) f.dynamic = true;
      }
    } else if (std::regex_search(line, m, edge)) {
      g.functions[m[1]].callees.insert(m[2]);
    } else if (line.rfind("node:", 0) == 0 || line.rfind("edge:", 0) == 0) {
      throw std::runtime_error(file + ":" + std::to_string(n) + ": a node or edge this reader does not understand");
    }
  }
}

int add_ci_dir(CallGraph& g, const std::string& dir) {
  int files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".ci") continue;
    std::ifstream f(e.path());
    std::stringstream text;
    text << f.rdbuf();
    add_ci(g, text.str(), e.path().string());
    ++files;
  }
  return files;
}

Bound stack_bound(const CallGraph& g, const std::string& root) {
  Bound out;
  std::map<std::string, Bound> done;  // each function's bound, once
  std::set<std::string> open;         // on the current path: a callee here is recursion
  std::function<const Bound&(const std::string&)> visit = [&](const std::string& t) -> const Bound& {
    if (auto it = done.find(t); it != done.end()) return it->second;
    Bound b;
    b.path.push_back(t);
    const auto it = g.functions.find(t);
    if (t == "__indirect_call") {
      b.problems.push_back("a call through a pointer (its target is unknown)");
    } else if (it == g.functions.end() || !it->second.has_frame) {
      if (is_leaf_helper(t))
        b.bytes = kLeafFrame;
      else
        b.problems.push_back(t + ": no frame in any .ci given (a function outside them)");
    } else {
      const Function& f = it->second;
      if (f.dynamic) b.problems.push_back(t + " (" + f.name + "): a frame of dynamic size");
      open.insert(t);
      std::uint32_t deepest = 0;
      std::vector<std::string> tail;
      for (const std::string& c : f.callees) {
        if (open.count(c) != 0u) {
          b.problems.push_back("recursion: " + t + " (" + f.name + ") calls " + c);
          continue;
        }
        const Bound& cb = visit(c);
        for (const std::string& p : cb.problems)
          if (std::find(b.problems.begin(), b.problems.end(), p) == b.problems.end()) b.problems.push_back(p);
        if (cb.bytes >= deepest) {
          deepest = cb.bytes;
          tail = cb.path;
        }
      }
      open.erase(t);
      b.bytes = f.frame + deepest;
      b.path.insert(b.path.end(), tail.begin(), tail.end());
    }
    return done.emplace(t, std::move(b)).first->second;
  };
  if (g.functions.count(root) == 0u) {
    out.problems.push_back(root + ": not in the call graph");
    return out;
  }
  out = visit(root);
  return out;
}

}  // namespace stackbound

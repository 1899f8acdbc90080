#pragma once
// The worst-case stack of a function from GCC's call graph: -fcallgraph-info=su writes one VCG file (.ci) per
// translation unit, a node per function with its frame ("48 bytes (static)") and an edge per call site. The bound
// of a function is its frame plus the largest bound among its callees, over every file given (an inline function
// defined in several units counts with its largest frame and the union of its calls).
//
// What makes a bound unknowable is reported, never guessed: a call through a pointer (GCC's __indirect_call), a
// recursive cycle, a frame of dynamic size (alloca, VLA; "dynamic,bounded" is taken as bounded), and a callee with
// no frame in any file. The C library's and the compiler runtime's leaf helpers (memcpy, memset, memmove, sqrtf,
// __aeabi_*), which have no .ci, count with kLeafFrame bytes each. Host tool for tests (throws).
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace stackbound {

inline constexpr std::uint32_t kLeafFrame = 64;  // bytes: a generous frame for newlib's and libgcc's leaf helpers

struct Function {
  std::string name;              // the demangled label's first line
  std::uint32_t frame = 0;       // bytes
  bool has_frame = false;        // defined in a file given (a node with "N bytes (...)")
  bool dynamic = false;          // "dynamic" without "bounded"
  std::set<std::string> callees; // titles (mangled)
};

struct CallGraph {
  std::map<std::string, Function> functions;  // by title
};

// Adds one .ci file's text (the file's name for errors).
void add_ci(CallGraph& g, const std::string& text, const std::string& file);
// Every .ci under `dir`, recursively; the number of files read.
int add_ci_dir(CallGraph& g, const std::string& dir);

struct Bound {
  std::uint32_t bytes = 0;
  std::vector<std::string> path;     // titles from the root to the deepest frame
  std::vector<std::string> problems; // why the bound is not a bound (empty: it is)
};

// The bound of `root` (a title: mangled, or an extern "C" name).
Bound stack_bound(const CallGraph& g, const std::string& root);

}  // namespace stackbound

// The kernel's per-socket UDP drop counters for this process (node/udp_drops.hpp).
#include "node/udp_drops.hpp"

#include <dirent.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace node {

namespace {

// The inodes of the sockets among this process's file descriptors ("socket:[INODE]").
std::set<unsigned long> socket_inodes() {
  std::set<unsigned long> inodes;
  DIR* d = opendir("/proc/self/fd");
  if (d == nullptr) return inodes;
  char link[64];
  while (const dirent* e = readdir(d)) {
    const std::string path = std::string("/proc/self/fd/") + e->d_name;
    const ssize_t n = readlink(path.c_str(), link, sizeof link - 1);
    if (n <= 0) continue;
    link[n] = '\0';
    unsigned long inode = 0;
    if (std::sscanf(link, "socket:[%lu]", &inode) == 1) inodes.insert(inode);
  }
  closedir(d);
  return inodes;
}

// Adds the drops of the rows of `table` (/proc/net/udp's layout) whose inode is in `inodes`; false if unreadable.
bool add_drops(const char* table, const std::set<unsigned long>& inodes, std::uint64_t& drops) {
  std::ifstream in(table);
  if (!in) return false;
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    // sl local rem st tx_queue:rx_queue tr:tm->when retrnsmt uid timeout inode ref pointer drops
    std::istringstream row(line);
    std::string sl, local, rem, st, queues, timer, retr, uid, timeout, pointer;
    unsigned long inode = 0, ref = 0;
    std::uint64_t row_drops = 0;
    if (!(row >> sl >> local >> rem >> st >> queues >> timer >> retr >> uid >> timeout >> inode >> ref >> pointer >>
          row_drops))
      continue;
    if (inodes.count(inode) != 0) drops += row_drops;
  }
  return true;
}

}  // namespace

std::optional<std::uint64_t> udp_receive_drops() {
  const std::set<unsigned long> inodes = socket_inodes();
  std::uint64_t drops = 0;
  const bool v4 = add_drops("/proc/net/udp", inodes, drops);
  const bool v6 = add_drops("/proc/net/udp6", inodes, drops);
  if (!v4 && !v6) return std::nullopt;
  return drops;
}

}  // namespace node

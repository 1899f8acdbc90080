#pragma once
// Datagrams the kernel dropped on this process's UDP sockets because their receive buffers were full: the drops
// column of /proc/net/udp and /proc/net/udp6 for the socket inodes in /proc/self/fd. What a live node loses before
// LCM sees it (an LCM message of several fragments is lost when one of them is). Linux only; host only.
#include <cstdint>
#include <optional>

namespace node {

// Summed over every UDP socket this process holds; empty when /proc cannot be read.
std::optional<std::uint64_t> udp_receive_drops();

}  // namespace node

#pragma once
// A fuzz input as the files of a dataset folder: the bytes from `begin` split at their first form feeds, one part per
// name (the last takes the rest), each written to dir/name. For the importers that read a folder of files.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

namespace fuzz {

inline void write_folder(const std::string& dir, const char* const* names, int count, const std::uint8_t* data,
                         std::size_t size, std::size_t begin) {
  for (int k = 0; k < count; ++k) {
    std::size_t end = begin;
    while (k + 1 < count && end < size && data[end] != '\f') ++end;
    if (k + 1 == count) end = size;
    std::ofstream f(dir + "/" + names[k], std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data + begin), static_cast<std::streamsize>(end - begin));
    begin = end < size ? end + 1 : size;
  }
}

}  // namespace fuzz

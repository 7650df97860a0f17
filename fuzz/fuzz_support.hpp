#pragma once
// Shared by the fuzz targets: the input goes to a file (the readers under test take paths, as the CLI gives
// them), and every error a reader may report is an InputError; anything else escaping is a finding.

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "vascsim/core/error.hpp"

namespace vascsim::fuzz {

/// Writes `size` bytes to a file of this process under /dev/shm (or the temp folder) with `extension`.
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size,
                                         const std::string& extension) {
  static const std::filesystem::path dir = std::filesystem::exists("/dev/shm")
                                               ? std::filesystem::path("/dev/shm")
                                               : std::filesystem::temp_directory_path();
  const std::filesystem::path file = dir / ("vascsim-fuzz-" + std::to_string(getpid()) + extension);
  // Removed when the process ends.
  static struct Cleanup {
    std::set<std::filesystem::path> files;
    ~Cleanup() {
      std::error_code ignored;
      for (const auto& f : files) std::filesystem::remove(f, ignored);
    }
  } cleanup;
  cleanup.files.insert(file);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

/// Runs `read` and accepts InputError only (NumericalError too where a reader computes).
template <class Read>
void expect_clean(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const NumericalError&) {
  }
}

}  // namespace vascsim::fuzz

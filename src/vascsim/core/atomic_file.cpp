#include "vascsim/core/atomic_file.hpp"

#include <fmt/format.h>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "vascsim/core/error.hpp"

namespace vascsim {

void write_file_atomically(const std::filesystem::path& file, std::string_view content) {
  std::filesystem::path temp = file;
  temp += ".tmp";
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw InputError(fmt::format("{}: cannot write: {}", file.string(), why));
  };
  std::FILE* out = std::fopen(temp.c_str(), "wb");
  if (out == nullptr) fail(std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), out) == content.size();
  const bool flushed = std::fflush(out) == 0;
  const int error = errno;
  const bool closed = std::fclose(out) == 0;
  if (!written || !flushed || !closed)
    fail(fmt::format("{} (disk full?)", std::strerror(error ? error : errno)));
  std::error_code ec;
  std::filesystem::rename(temp, file, ec);
  if (ec) fail(ec.message());
}

}  // namespace vascsim

#pragma once
// `vascsim ...` in-process through run_cli, with what it printed, and a scratch folder per test: for the
// tests of error exits and output files.

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "vascsim/app/cli.hpp"

namespace vascsim::test {

struct CliCapture {
  int code = -1;
  std::string out, err;
  std::vector<std::string>
      messages;  ///< lines of err that are neither log lines ("[level] msg") nor progress lines
  bool err_has(const std::string& s) const { return err.find(s) != std::string::npos; }
  bool out_has(const std::string& s) const { return out.find(s) != std::string::npos; }
};

inline CliCapture run_cli_captured(const std::vector<std::string>& args) {
  // run_cli installs a logger writing into `err`; the previous one comes back before `err` is gone.
  const auto previous = spdlog::default_logger();
  std::ostringstream out, err;
  CliCapture r;
  r.code = run_cli(args, out, err);
  spdlog::set_default_logger(previous);
  r.out = out.str();
  r.err = err.str();
  std::istringstream lines(r.err);
  // Progress lines when err is not a terminal: "<scene>: 3/10 (30%) 1.2s ..." (app/progress.cpp).
  static const std::regex progress(R"(^\S+: \d+/\d+ \(\d+%\) )");
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] != '[' && !std::regex_search(line, progress)) r.messages.push_back(line);
  return r;
}

/// A fresh, empty folder for the current test under testing::TempDir().
inline std::filesystem::path fresh_test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto d = std::filesystem::path(::testing::TempDir()) / ("vascsim_" + std::to_string(::getpid())) /
                 (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string write_file(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
  return file.string();
}

inline std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace vascsim::test

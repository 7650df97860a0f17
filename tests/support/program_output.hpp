#pragma once
// Running one of the project's programs as a user would (popen): its exit code and everything it printed
// (stdout and stderr), for the tests of error exits.

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace vascsim::test {

struct ProgramOutput {
  int exit_code = -1;  ///< -1: did not exit normally
  std::string output;  ///< stdout + stderr
  std::size_t lines() const {
    std::size_t n = 0;
    for (char c : output) n += c == '\n';
    return n;
  }
};

/// Runs `env program args` in a shell (env: e.g. "env -u DISPLAY", may be empty).
inline ProgramOutput run_program(const std::string& env, const std::string& program,
                                 const std::string& args) {
  const std::string cmd = env + " \"" + program + "\" " + args + " 2>&1";
  ProgramOutput r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) r.output += buffer;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace vascsim::test

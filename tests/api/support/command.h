#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace mobot::testing {

// What a finished command left: its exit code (-1 killed by a signal, -2 still running at the
// timeout, then killed) and everything it wrote.
struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs argv[0] (a path) with the arguments, no stdin, stdout and stderr captured apart.
CommandResult run_command(const std::vector<std::string>& argv,
                          std::chrono::milliseconds timeout = std::chrono::seconds(30));

// `mobotd ARGS...` (the binary under test).
CommandResult run_mobotd(const std::vector<std::string>& args,
                         std::chrono::milliseconds timeout = std::chrono::seconds(30));

}  // namespace mobot::testing

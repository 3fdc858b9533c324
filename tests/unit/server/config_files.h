// Config files for the tests of load_config: each text written to a file of its own.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "server/config.h"

namespace mobot::server::test {

inline std::filesystem::path write_config(const std::string& text) {
  static int counter = 0;
  const auto file =
      std::filesystem::temp_directory_path() /
      ("mobot_config_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".yaml");
  std::ofstream(file) << text;
  return file;
}

// What load_config says of the text, or "<no error>".
inline std::string load_error_of(const std::string& text) {
  try {
    load_config(write_config(text));
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "<no error>";
}

}  // namespace mobot::server::test

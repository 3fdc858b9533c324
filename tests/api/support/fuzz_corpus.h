#pragma once

// The inputs a libFuzzer target kept (its corpus), for the API tests that replay them against a
// real mobotd: the seeds of tests/fuzz/corpus/TARGET, and the directories named in an environment
// variable (colon-separated), which deploy/test.sh sets to the corpus its fuzzing phase grew.

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace mobot::testing {

inline std::vector<std::filesystem::path> fuzz_corpus_files(const std::string& target,
                                                            const char* directories_variable) {
  namespace fs = std::filesystem;
  std::vector<fs::path> directories{fs::path(MOBOT_SOURCE_ROOT) / "tests/fuzz/corpus" / target};
  if (const char* extra = std::getenv(directories_variable)) {
    std::stringstream list(extra);
    for (std::string directory; std::getline(list, directory, ':');) {
      if (!directory.empty()) directories.emplace_back(directory);
    }
  }
  std::vector<fs::path> files;
  for (const fs::path& directory : directories) {
    for (const auto& entry : fs::directory_iterator(directory)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

inline std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The printable start of an input, for a failure message.
inline std::string printable(std::string_view bytes, std::size_t at_most = 200) {
  std::string text;
  for (const char c : bytes.substr(0, at_most)) text += (c >= 0x20 && c < 0x7F) ? c : '.';
  return text;
}

}  // namespace mobot::testing

#pragma once

#include <string>
#include <vector>

namespace mobot::tools {

// The lines of a text file, plain or gzip-compressed (recognised by its magic bytes and
// decompressed by piping through `gzip -dc`, so the tools need no zlib). Throws
// std::runtime_error when the file cannot be read.
std::vector<std::string> read_text_lines(const std::string& path);

}  // namespace mobot::tools

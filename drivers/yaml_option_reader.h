#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <sstream>
#include <string>

namespace mobot::drivers {

// Reads one YAML section of the config (a plugin's, a device's), naming every bad key by its full
// path ("planners.astar.x"), throwing `Error`. Keys the reader is not asked for are refused, so a
// misspelt option never goes unnoticed.
template <class Error>
class YamlOptionReader {
 public:
  YamlOptionReader(const YAML::Node& section, std::string path)
      : section_(section), path_(std::move(path)) {
    if (section_ && !section_.IsNull() && !section_.IsMap())
      throw Error(path_ + ": expected a mapping");
  }
  ~YamlOptionReader() = default;

  void number(const char* key, double& out, double min, double max) {
    const YAML::Node node = take(key);
    if (!node) return;
    try {
      out = node.as<double>();
    } catch (const YAML::Exception&) {
      throw Error(path_ + "." + key + ": expected a number");
    }
    if (!(out >= min && out <= max)) {
      std::ostringstream message;
      message << path_ << "." << key << ": " << out << " is outside the allowed range [" << min
              << ", " << max << "]";
      throw Error(message.str());
    }
  }

  void integer(const char* key, int& out, int min, int max) {
    double value = out;
    number(key, value, min, max);
    out = static_cast<int>(value);
  }

  void flag(const char* key, bool& out) {
    const YAML::Node node = take(key);
    if (!node) return;
    try {
      out = node.as<bool>();
    } catch (const YAML::Exception&) {
      throw Error(path_ + "." + key + ": expected true or false");
    }
  }

  void text(const char* key, std::string& out) {
    const YAML::Node node = take(key);
    if (!node) return;
    if (!node.IsScalar()) throw Error(path_ + "." + key + ": expected a string");
    out = node.as<std::string>();
  }

  // The raw node of a key with a shape of its own (a list); marks it read.
  YAML::Node node(const char* key) { return take(key); }

  // Call after reading every option: refuses the keys nobody read.
  void done() const {
    if (!section_ || !section_.IsMap()) return;
    for (const auto& entry : section_) {
      const auto key = entry.first.as<std::string>();
      if (!read_.contains(key)) throw Error(path_ + "." + key + ": unknown key");
    }
  }

  const std::string& path() const { return path_; }

 private:
  YAML::Node take(const char* key) {
    read_.insert(key);
    if (!section_ || !section_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    return section_[key];
  }

  YAML::Node section_;
  std::string path_;
  std::set<std::string> read_;
};

}  // namespace mobot::drivers

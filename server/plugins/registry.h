#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "server/plugins/plugin_context.h"

namespace mobot::server {

// Names of one kind of plugin (planners, path trackers, estimators, kinematic models, costmap
// layers) mapped to what makes them. Each plugin brings its options parser: it reads the
// plugin's own YAML section (null when the config has none: every option at its default), throws
// ConfigError naming the bad key, and returns a Maker that builds instances with those options.
template <class Interface>
class Registry {
 public:
  using Maker = std::function<std::unique_ptr<Interface>()>;
  using Parser = std::function<Maker(const YAML::Node& section, const PluginContext& context)>;

  // `kind` names the plugin in messages ("planner"); `section` is the config's mapping that holds
  // one section per plugin ("planners" -> planners.astar).
  Registry(std::string kind, std::string section)
      : kind_(std::move(kind)), section_(std::move(section)) {}

  // One registration per plugin; a name registered twice is a programming error.
  void add(std::string name, Parser parser) {
    if (!parsers_.emplace(name, std::move(parser)).second) {
      throw std::logic_error(kind_ + " '" + name + "' is registered twice");
    }
  }

  bool contains(std::string_view name) const {
    return parsers_.find(std::string(name)) != parsers_.end();
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, parser] : parsers_) out.push_back(name);
    return out;
  }
  const std::string& kind() const { return kind_; }
  const std::string& section() const { return section_; }

  // The Maker for `name` with its section of `root` (the whole config document). Throws
  // ConfigError for an unknown name (listing the known ones) or a bad option.
  Maker configure(std::string_view name, const YAML::Node& root,
                  const PluginContext& context) const {
    const auto parser = parsers_.find(std::string(name));
    if (parser == parsers_.end()) throw unknown(name);
    // Constructed, not assigned: yaml-cpp's assignment of a missing key's node throws.
    const YAML::Node section =
        root && root[section_] ? YAML::Node(root[section_][std::string(name)]) : YAML::Node();
    return parser->second(section, context);
  }

  // A Maker per registered name, each with its section of `root`; also refuses a section in the
  // config for a name nobody registered (a misspelt plugin would otherwise be ignored).
  std::map<std::string, Maker, std::less<>> configure_all(const YAML::Node& root,
                                                          const PluginContext& context) const {
    if (root && root[section_]) {
      const YAML::Node sections = root[section_];
      if (!sections.IsMap())
        throw ConfigError(section_ + ": expected a mapping of " + kind_ + " names");
      for (const auto& entry : sections) {
        const auto name = entry.first.as<std::string>();
        if (!contains(name)) throw unknown(name, section_ + "." + name);
      }
    }
    std::map<std::string, Maker, std::less<>> makers;
    for (const auto& [name, parser] : parsers_)
      makers.emplace(name, configure(name, root, context));
    return makers;
  }

  ConfigError unknown(std::string_view name, const std::string& where = {}) const {
    std::string list;
    for (const auto& [known, parser] : parsers_) list += (list.empty() ? "" : ", ") + known;
    return ConfigError((where.empty() ? section_ : where) + ": no " + kind_ + " is called '" +
                       std::string(name) + "' (known: " + list + ")");
  }

 private:
  std::string kind_;
  std::string section_;
  std::map<std::string, Parser, std::less<>> parsers_;
};

// The configured plugins of one kind: what the runtime makes instances from, by name.
template <class Interface>
class PluginSet {
 public:
  using Maker = typename Registry<Interface>::Maker;

  PluginSet() = default;
  PluginSet(const Registry<Interface>& registry, const YAML::Node& root,
            const PluginContext& context)
      : makers_(registry.configure_all(root, context)) {}

  // A new instance, or null when no plugin has that name.
  std::unique_ptr<Interface> make(std::string_view name) const {
    const auto maker = makers_.find(name);
    return maker == makers_.end() ? nullptr : maker->second();
  }
  bool contains(std::string_view name) const { return makers_.find(name) != makers_.end(); }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, maker] : makers_) out.push_back(name);
    return out;
  }

 private:
  std::map<std::string, Maker, std::less<>> makers_;
};

}  // namespace mobot::server

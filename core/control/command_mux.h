#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/msgs/twist.h"

namespace mobot::control {

// One input of the mux. A command from a source holds for timeout_s (or the ttl given with it);
// after that the source falls silent and a lower-priority source, or a stop, takes over.
struct MuxSource {
  std::string name;
  int priority = 0;  // higher wins
  double timeout_s = 1.0;
};

// docs/algorithms.md C6: priority arbitration with time-outs (safety > IR safety > teleop >
// navigation).
class CommandMux {
 public:
  struct Selection {
    std::optional<std::string> source;  // nullopt: every source is silent, so the base stops
    msgs::Twist command;
  };

  explicit CommandMux(std::vector<MuxSource> sources);

  // Returns false when no source has that name.
  bool submit(std::string_view source, const msgs::Twist& command, double now_s,
              std::optional<double> ttl_s = std::nullopt);
  void clear(std::string_view source);
  void clear_all();
  Selection select(double now_s) const;
  bool is_active(std::string_view source, double now_s) const;

 private:
  struct Slot {
    MuxSource source;
    msgs::Twist command;
    std::optional<double> expires_s;
  };
  Slot* find(std::string_view source);
  const Slot* find(std::string_view source) const;

  std::vector<Slot> slots_;  // sorted by priority, highest first
};

}  // namespace mobot::control

#include "core/control/command_mux.h"

#include <algorithm>
#include <stdexcept>

namespace mobot::control {

CommandMux::CommandMux(std::vector<MuxSource> sources) {
  for (auto& source : sources) {
    if (find(source.name) != nullptr) {
      throw std::invalid_argument("command mux source '" + source.name + "' given twice");
    }
    slots_.push_back({std::move(source), {}, std::nullopt});
  }
  std::stable_sort(slots_.begin(), slots_.end(), [](const Slot& a, const Slot& b) {
    return a.source.priority > b.source.priority;
  });
}

bool CommandMux::submit(std::string_view source, const msgs::Twist& command, double now_s,
                        std::optional<double> ttl_s) {
  Slot* slot = find(source);
  if (slot == nullptr) return false;
  slot->command = command;
  slot->expires_s = now_s + ttl_s.value_or(slot->source.timeout_s);
  return true;
}

void CommandMux::clear(std::string_view source) {
  if (Slot* slot = find(source)) slot->expires_s.reset();
}

void CommandMux::clear_all() {
  for (auto& slot : slots_) slot.expires_s.reset();
}

CommandMux::Selection CommandMux::select(double now_s) const {
  for (const auto& slot : slots_) {
    if (slot.expires_s && now_s < *slot.expires_s) return {slot.source.name, slot.command};
  }
  return {};
}

bool CommandMux::is_active(std::string_view source, double now_s) const {
  const Slot* slot = find(source);
  return slot != nullptr && slot->expires_s && now_s < *slot->expires_s;
}

CommandMux::Slot* CommandMux::find(std::string_view source) {
  auto it = std::find_if(slots_.begin(), slots_.end(),
                         [&](const Slot& slot) { return slot.source.name == source; });
  return it == slots_.end() ? nullptr : &*it;
}

const CommandMux::Slot* CommandMux::find(std::string_view source) const {
  return const_cast<CommandMux*>(this)->find(source);
}

}  // namespace mobot::control

#include "tools/emulate/devices/timed_replies.h"

#include <algorithm>

namespace mobot::emulate {

std::vector<std::uint8_t> TimedReplies::take_due(double now_s) {
  std::vector<std::uint8_t> out;
  const auto due =
      std::stable_partition(pending_.begin(), pending_.end(),
                            [now_s](const Reply& reply) { return reply.due_s <= now_s; });
  for (auto it = pending_.begin(); it != due; ++it) {
    out.insert(out.end(), it->text.begin(), it->text.end());
  }
  pending_.erase(pending_.begin(), due);
  return out;
}

}  // namespace mobot::emulate

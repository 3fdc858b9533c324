#include "drivers/serial/reopen_backoff.h"

#include <algorithm>

namespace mobot::drivers::serial {

ReopenBackoff::ReopenBackoff(ReopenBackoffOptions options) : options_(options) {}

double ReopenBackoff::next_delay_s() {
  delay_s_ = delay_s_ <= 0.0 ? options_.first_delay_s
                             : std::min(delay_s_ * options_.factor, options_.max_delay_s);
  return delay_s_;
}

}  // namespace mobot::drivers::serial

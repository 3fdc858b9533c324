#pragma once

namespace mobot::drivers::serial {

struct ReopenBackoffOptions {
  double first_delay_s = 0.1;
  double factor = 2.0;
  // A device that comes back is found within this long: the cap is what a user waits at most
  // after plugging a cable back in.
  double max_delay_s = 2.0;
};

// How long to wait before the next attempt to reopen a device that failed: exponential, capped,
// and back to the first delay once the device answered again.
class ReopenBackoff {
 public:
  explicit ReopenBackoff(ReopenBackoffOptions options = {});

  // The delay before the next attempt, growing with each call.
  double next_delay_s();
  // The device answers again: the next failure starts from the first delay.
  void reset() { delay_s_ = 0.0; }

 private:
  ReopenBackoffOptions options_;
  double delay_s_ = 0.0;
};

}  // namespace mobot::drivers::serial

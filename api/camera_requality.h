#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "api/frame_codec.h"
#include "core/msgs/image.h"

namespace mobot::api {

// Compresses camera frames again at the JPEG qualities that stream clients capped theirs at, on a
// thread of its own: a 640 x 480 frame takes a few milliseconds per quality, which neither the
// control loop (it publishes) nor the io threads (they write to every client) can spare. Each
// quality is done once per frame, whatever the number of clients that asked for it. Only the
// newest frame waits: one that comes while another is being done replaces the waiting one, as the
// camera itself drops frames nobody takes.
class CameraRequality {
 public:
  // The frame at each quality asked for, in the order asked, with the stamp it was published with.
  using Done = std::function<void(const FrameStamp& stamp,
                                  std::vector<std::pair<int, msgs::Image>> variants)>;

  explicit CameraRequality(Done done);
  CameraRequality(const CameraRequality&) = delete;
  CameraRequality& operator=(const CameraRequality&) = delete;

  // qualities: 1..100, each below the frame's own. Any thread.
  void submit(msgs::Image image, const FrameStamp& stamp, std::vector<int> qualities);

 private:
  struct Job {
    msgs::Image image;
    FrameStamp stamp;
    std::vector<int> qualities;
  };

  void run(const std::stop_token& stop);

  Done done_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::optional<Job> job_;
  std::jthread thread_;  // last: joined before the rest goes
};

}  // namespace mobot::api

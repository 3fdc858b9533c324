#pragma once

#include "api/stream_hub.h"
#include "server/bus.h"
#include "server/recorder.h"

namespace mobot::server {

// The stream hub hears every topic of the bus and sends a batch at each flush.
void connect_stream_hub(Bus& bus, api::StreamHub& hub);

// The recorder keeps every event and samples the pose at `trajectory_rate_hz` of robot time.
void connect_recorder(Bus& bus, Recorder& recorder, double trajectory_rate_hz);

}  // namespace mobot::server

#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/json_request.h"
#include "api/ports/token_admin_port.h"

namespace mobot::api {

// The ops a stream client sends as JSON text messages (docs/api.md, "Client ops"), parsed and
// checked before the session acts on any of them.
struct SubscribeRequest {
  std::vector<std::string> topics;  // as given: the session knows which exist
  bool binary = true;
  std::int64_t min_interval_us = 0;  // from max_rate_hz; 0: every frame
  int camera_quality = 0;            // 0: the camera's own
  // The connection's byte-rate cap (kbit/s; 0: none); absent: as it was.
  std::optional<double> max_kbps;
};

struct UnsubscribeRequest {
  std::vector<std::string> topics;
};

struct PingRequest {
  nlohmann::json id;  // echoed in the pong; null when absent
};

// A teleop on the stream is a lease: `seq` orders a connection's commands (one not above the last
// is dropped), `sent_ms` is the client's clock when it sent it, echoed for its round trip.
struct StreamTeleopRequest {
  TeleopRequest command;
  std::optional<std::uint64_t> seq;
  std::optional<double> sent_ms;
};

struct EstopRequest {
  bool engaged = true;
};

using StreamRequest = std::variant<SubscribeRequest, UnsubscribeRequest, StreamTeleopRequest,
                                   PingRequest, EstopRequest>;

// A client message read as a JSON object with a string "op", before the op's own fields are
// looked at: what an error reply can name. Throws ApiError malformed_json or missing_op.
struct StreamMessage {
  nlohmann::json body;
  std::string op;
};
StreamMessage read_stream_message(std::string_view text);

// The request a message makes. Throws ApiError with the code the session answers with:
// unknown_op, invalid_topics, invalid_encoding, invalid_field, missing_field and, for a teleop or
// an e-stop from a client below the operator role, forbidden (before its fields are looked at).
StreamRequest parse_stream_request(const StreamMessage& message, Role role);

// What an error reply says of the message it answers, so that a client with several requests in
// flight knows which one was refused: `request_op` (when the op is one of the protocol's) and, for
// a teleop, its `seq` as sent (when it is a number).
nlohmann::json request_identity(const StreamMessage& message);
nlohmann::json request_identity(std::string_view op, std::optional<std::uint64_t> seq = {});

// Both steps; also throws malformed_json and missing_op.
StreamRequest parse_stream_request(std::string_view text, Role role);

}  // namespace mobot::api

#include "api/rest_reply.h"

namespace mobot::api {
namespace {

// Only what a response copies from its request: the version and whether to keep the connection.
Request head_of(const Request& request) {
  Request head{request.method(), request.target(), request.version()};
  head.keep_alive(request.keep_alive());
  return head;
}

}  // namespace

Replier::Replier(const Request& request, Responder respond, ClientContext client)
    : state_(std::make_shared<State>(head_of(request), std::move(respond), std::move(client))) {}

void Replier::send(Response response) const noexcept {
  if (state_->answered.exchange(true)) return;
  // Moved out so that the session the responder holds is released as soon as it has its answer,
  // however long the port keeps its copy of the Completion.
  Responder respond = std::move(state_->respond);
  try {
    respond(std::move(response));
  } catch (...) {
    // The session could not take the response (out of memory): its client sees the connection
    // end when the session is released.
  }
}

}  // namespace mobot::api

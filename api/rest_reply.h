#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "api/api_error.h"
#include "api/http_types.h"
#include "api/ports/result.h"

namespace mobot::api {

// The connection a request came on: its id (unique in this process) and the peer's address.
struct ClientContext {
  std::uint64_t id = 0;
  std::string address;
};

// Takes the one response to a request. Called once, from any thread.
using Responder = std::function<void(Response)>;

// What a REST handler returns: its response, or kReplyLater when a port's Completion sends it.
using Handled = std::optional<Response>;
inline constexpr std::nullopt_t kReplyLater = std::nullopt;

// The way back to the client of one request. Copies share one answer: the first response wins and
// later ones are dropped, so a port that completes and then throws, or completes twice, still
// answers once. Nothing here throws into its caller: a Completion runs on the robot's threads (the
// control loop, a worker, the recorder's writer), which must not see HTTP's failures.
class Replier {
 public:
  Replier(const Request& request, Responder respond, ClientContext client = {});

  // The request line a deferred response is built for: version and keep-alive, no body.
  const Request& head() const { return state_->head; }
  const ClientContext& client() const { return state_->client; }

  // Runs `handle` and sends the response it returns or the error it throws.
  template <class Handle>
  void answer(Handle&& handle) const noexcept;

  // The Completion of a port call: `render(head(), value)` makes the response to a value (and may
  // throw ApiError), a refusal becomes its error response.
  template <class T, class Render>
  Completion<T> completion(Render render) const;

 private:
  struct State {
    // Spelt out: clang before 16 does not make an aggregate from make_shared's parentheses.
    State(Request head_in, Responder respond_in, ClientContext client_in)
        : head(std::move(head_in)), respond(std::move(respond_in)), client(std::move(client_in)) {}

    Request head;
    Responder respond;
    ClientContext client;
    std::atomic<bool> answered{false};
  };

  void send(Response response) const noexcept;

  std::shared_ptr<State> state_;
};

template <class Handle>
void Replier::answer(Handle&& handle) const noexcept {
  try {
    try {
      if (Handled response = handle()) send(std::move(*response));
    } catch (const ApiError& error) {
      send(error_response(head(), error.http_status(), error.code(), error.what()));
    } catch (const DomainException& error) {
      send(domain_error_response(head(), error.error()));
    } catch (const std::exception& error) {
      send(error_response(head(), 500, "internal_error", error.what()));
    } catch (...) {
      send(error_response(head(), 500, "internal_error", "unexpected failure"));
    }
  } catch (...) {
    // Not even the error response could be built (out of memory): there is nothing left to send.
  }
}

template <class T, class Render>
Completion<T> Replier::completion(Render render) const {
  return [replier = *this, render = std::move(render)](Result<T> result) {
    replier.answer([&]() -> Handled {
      if (!result.ok()) return domain_error_response(replier.head(), result.error());
      return render(replier.head(), result.value());
    });
  };
}

}  // namespace mobot::api

#pragma once

#include <utility>

#include "api/ports/result.h"
#include "server/recorder.h"
#include "server/tick_context.h"

namespace mobot::server {

// Calls `done` with `value` once the command's state is published and what the recorder holds
// then is committed: an acknowledged command's events survive a kill right after the reply.
template <class T>
void after_commit(Recorder& recorder, TickContext& context, api::Completion<T> done, T value) {
  context.then([&recorder, done = std::move(done), value = std::move(value)]() mutable {
    recorder.flush_async(
        [done = std::move(done), value = std::move(value)]() mutable { done(std::move(value)); });
  });
}

}  // namespace mobot::server

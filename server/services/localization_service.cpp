#include "server/services/localization_service.h"

#include "server/services/after_commit.h"
#include "server/services/refusals.h"

namespace mobot::server {
namespace {

// The estimator that can localize globally (docs/algorithms.md E4).
constexpr const char* kGlobalMethod = "particle_filter";

}  // namespace

LocalizationService::LocalizationService(Runtime& runtime, Recorder& recorder,
                                         EstimateStage& estimate, const ConfiguredPlugins& plugins)
    : runtime_(runtime), recorder_(recorder), estimate_(estimate), plugins_(plugins) {}

std::vector<std::string> LocalizationService::localization_methods() const {
  return plugins_.estimators.names();
}

void LocalizationService::set_localization_method(const std::string& method,
                                                  api::Completion<std::string> done) {
  runtime_.post([this, method, done = std::move(done)](TickContext& context) mutable {
    if (context.mapping) return done(mapping_active());
    if (!estimate_.select(method, context)) {
      return done(api::DomainError{api::ErrorKind::kInvalid, "unknown_method",
                                   "no localization method is called '" + method + "'"});
    }
    context.event("localization", {{"action", "method"}, {"method", method}});
    after_commit(recorder_, context, std::move(done), method);
  });
}

void LocalizationService::localize_globally(api::Completion<std::string> done) {
  runtime_.post([this, done = std::move(done)](TickContext& context) mutable {
    if (context.mapping) return done(mapping_active());
    if (!estimate_.has_map()) {
      return done(api::DomainError{api::ErrorKind::kConflict, "no_map",
                                   "global localization needs an active map"});
    }
    if (!plugins_.estimators.contains(kGlobalMethod)) {
      return done(api::DomainError{api::ErrorKind::kConflict, "unsupported_method",
                                   "this robot has no particle filter"});
    }
    estimate_.select(kGlobalMethod, context);  // kept as it is when already running
    if (!estimate_.start_global_localization(context)) {
      return done(api::DomainError{api::ErrorKind::kConflict, "no_map",
                                   "the active map has no free space to localize in"});
    }
    context.event("localization", {{"action", "global"}, {"method", kGlobalMethod}});
    after_commit(recorder_, context, std::move(done), std::string(kGlobalMethod));
  });
}

}  // namespace mobot::server

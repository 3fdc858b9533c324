#include "server/services/sim_service.h"

#include "server/services/after_commit.h"
#include "server/services/refusals.h"

#include <stdexcept>

namespace mobot::server {
namespace {

api::DomainError pose_in_obstacle() {
  return {api::ErrorKind::kInvalid, "pose_in_obstacle", "the robot does not fit at that pose"};
}

}  // namespace

SimService::SimService(drivers::SimControl& sim, Runtime& runtime, Recorder& recorder,
                       MapCatalog& maps, ResetStages stages)
    : sim_(sim), runtime_(runtime), recorder_(recorder), maps_(maps), stages_(stages) {
  // The truth is known before the first tick: a reader right after start-up sees where the robot
  // stands, not the origin. (Posted before the loop starts: it runs with the start-up commands.)
  runtime_.post([this](TickContext& context) {
    context.truth = api::SimTruth{context.now_s, sim_.true_pose(), sim_.collision_count(),
                                  sim_.true_steering_rad()};
  });
}

std::vector<api::WorldInfo> SimService::list_worlds() const {
  std::vector<api::WorldInfo> out;
  for (const auto& world : sim_.worlds()) out.push_back({world.name, world.description});
  return out;
}

api::SimTruth SimService::sim_truth() const {
  const auto state = runtime_.state();
  return state->truth.value_or(api::SimTruth{state->robot.t_s, {}, 0, std::nullopt});
}

void SimService::sim_reset(const api::SimResetRequest& request, api::Completion<api::Done> done) {
  std::shared_ptr<const drivers::SimWorldChoice> world;
  if (request.world) {
    try {
      world = std::make_shared<const drivers::SimWorldChoice>(sim_.load_world(*request.world));
    } catch (const std::invalid_argument& error) {
      return done(api::DomainError{api::ErrorKind::kInvalid, "unknown_world", error.what()});
    }
    if (request.pose && !sim_.pose_is_free(*request.pose, world.get())) {
      return done(pose_in_obstacle());
    }
    maps_.ensure_named_map(world->name, world->surveyed_map, MapCatalog::Activation::kAlways);
  }
  runtime_.post([this, world, request, done = std::move(done)](TickContext& context) mutable {
    if (context.mapping) return done(mapping_active());
    if (!world && request.pose && !sim_.pose_is_free(*request.pose))
      return done(pose_in_obstacle());
    reset_on_loop(world, request, context);
    context.then([this, world, done = std::move(done)]() mutable {
      recorder_.flush_async([this, world, done = std::move(done)]() mutable {
        // A new world brings its map: in use before the reply.
        if (world) return maps_.reactivate(std::move(done));
        done(api::Done{});
      });
    });
  });
}

void SimService::kidnap(const geometry::Pose2D& pose, api::Completion<api::Done> done) {
  runtime_.post([this, pose, done = std::move(done)](TickContext& context) mutable {
    if (!sim_.pose_is_free(pose)) return done(pose_in_obstacle());
    sim_.teleport(pose);
    context.truth = api::SimTruth{context.now_s, pose, sim_.collision_count(), sim_.true_steering_rad()};
    context.event("sim_kidnap", {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}});
    after_commit(recorder_, context, std::move(done), api::Done{});
  });
}

void SimService::reset_on_loop(const std::shared_ptr<const drivers::SimWorldChoice>& world,
                               const api::SimResetRequest& request, TickContext& context) {
  stages_.navigate.end_active(navigation::GoalStatus::kCanceled, "reset", context);
  if (stages_.sweep) stages_.sweep->abort("reset", context);
  sim_.reset(world.get(), request.pose, request.seed);
  const geometry::Pose2D start = sim_.true_pose();
  stages_.estimate.reset(start, placement_covariance(), context);
  stages_.mux.drop_commands(context);
  // The truth the reply's readers see is the new one, not the last tick's.
  context.truth = api::SimTruth{context.now_s, start, sim_.collision_count(), sim_.true_steering_rad()};
  context.event("sim_reset", {{"world", sim_.world_name()},
                              {"x", start.x},
                              {"y", start.y},
                              {"theta", start.theta},
                              {"seed", sim_.seed()}});
}

void SimService::add_sim_obstacle(const api::SimObstacleRequest& request,
                                  api::Completion<int> done) {
  runtime_.post([this, request, done = std::move(done)](TickContext& context) mutable {
    try {
      const int id =
          sim_.add_obstacle(request.x_m, request.y_m, request.radius_m, request.height_m);
      context.then([done = std::move(done), id] { done(id); });
    } catch (const std::invalid_argument& error) {
      done(api::DomainError{api::ErrorKind::kInvalid, "invalid_obstacle", error.what()});
    }
  });
}

void SimService::remove_sim_obstacle(int id, api::Completion<api::Done> done) {
  runtime_.post([this, id, done = std::move(done)](TickContext& context) mutable {
    if (!sim_.remove_obstacle(id)) {
      return done(api::DomainError{api::ErrorKind::kNotFound, "unknown_obstacle",
                                   "no obstacle with this id"});
    }
    context.then([done = std::move(done)] { done(api::Done{}); });
  });
}

void SimService::add_sim_target(const api::SimTargetRequest& request,
                                api::Completion<int> done) {
  sim::MovingTargetSpec spec;
  spec.color = {static_cast<std::uint8_t>(request.color[0]),
                static_cast<std::uint8_t>(request.color[1]),
                static_cast<std::uint8_t>(request.color[2])};
  spec.radius_m = request.radius_m;
  spec.height_m = request.height_m;
  spec.path = request.path;
  spec.speed_mps = request.speed_mps;
  spec.loop = request.loop;
  runtime_.post([this, spec, done = std::move(done)](TickContext& context) mutable {
    try {
      const int id = sim_.add_target(spec);
      context.then([done = std::move(done), id] { done(id); });
    } catch (const std::invalid_argument& error) {
      done(api::DomainError{api::ErrorKind::kInvalid, "invalid_target", error.what()});
    }
  });
}

void SimService::remove_sim_target(int id, api::Completion<api::Done> done) {
  runtime_.post([this, id, done = std::move(done)](TickContext& context) mutable {
    if (!sim_.remove_target(id)) {
      return done(api::DomainError{api::ErrorKind::kNotFound, "unknown_target",
                                   "no target with this id"});
    }
    context.then([done = std::move(done)] { done(api::Done{}); });
  });
}

}  // namespace mobot::server

#include "server/services/control_service.h"

#include "server/services/refusals.h"

namespace mobot::server {
namespace {

std::string plan_error_message(planning::PlanError error) {
  switch (error) {
    case planning::PlanError::kGoalOutsideMap:
      return "the goal lies outside the active map";
    case planning::PlanError::kGoalInObstacle:
      return "the robot does not fit at the goal: it is in or too close to an obstacle";
    case planning::PlanError::kNoPath:
      return "no collision-free path leads from the robot to the goal";
    case planning::PlanError::kGoalInKeepout:
      return "the goal lies inside a keep-out zone";
    case planning::PlanError::kStartInObstacle:
      return "the robot is inside an obstacle and cannot get out";
    case planning::PlanError::kStartOutsideMap:
      return "the robot is outside the active map";
    case planning::PlanError::kInvalidPose:
      return "the goal is not a finite pose";
    case planning::PlanError::kNoMap:
      return "no map is active";
  }
  return "planning failed";
}

Eigen::Matrix3d to_matrix(const std::array<double, 9>& values) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      m(r, c) = values[static_cast<std::size_t>(r) * 3 + static_cast<std::size_t>(c)];
  }
  return m;
}

}  // namespace

api::DomainError plan_error(planning::PlanError error) {
  const auto kind = error == planning::PlanError::kInvalidPose ? api::ErrorKind::kInvalid
                    : error == planning::PlanError::kNoMap     ? api::ErrorKind::kConflict
                                                               : api::ErrorKind::kImpossible;
  return {kind, std::string(planning::error_code(error)), plan_error_message(error)};
}

ControlService::ControlService(Runtime& runtime, Recorder& recorder, ControlStages stages,
                               const kinematics::KinematicModel& kinematics,
                               const ConfiguredPlugins& plugins, NavigationSection defaults)
    : runtime_(runtime),
      recorder_(recorder),
      stages_(stages),
      kinematics_(kinematics),
      plugins_(plugins),
      defaults_(std::move(defaults)) {}

void ControlService::teleop(const msgs::Twist& command, int ttl_ms,
                            api::Completion<msgs::Twist> done) {
  runtime_.post([this, command, ttl_ms, done = std::move(done)](TickContext& context) mutable {
    if (stages_.mux.estop()) return done(estop_engaged());
    stages_.navigate.end_active(navigation::GoalStatus::kCanceled, "teleop_override", context);
    const msgs::Twist feasible = kinematics_.feasible(command);
    stages_.mux.submit_teleop(feasible, ttl_ms / 1000.0, context);
    context.then([done = std::move(done), feasible] { done(feasible); });
  });
}

void ControlService::set_estop(bool engaged, api::Completion<bool> done) {
  runtime_.post([this, engaged, done = std::move(done)](TickContext& context) mutable {
    if (engaged && !stages_.mux.estop()) {
      stages_.write_base.stop_now();
      stages_.navigate.end_active(navigation::GoalStatus::kCanceled, "estop", context);
    }
    // The robot is stopped now; the reply waits until the e-stop event is on disk, so an
    // acknowledged e-stop is in the run even if the server is killed right after.
    after_commit(recorder_, context, std::move(done), stages_.mux.set_estop(engaged, context));
  });
}

void ControlService::submit_goal(const api::GoalRequest& request,
                                 api::Completion<navigation::Goal> done) {
  if (!plugins_.planners.contains(request.planner)) {
    return done(api::DomainError{api::ErrorKind::kImpossible, "unsupported_planner",
                                 "the planner '" + request.planner + "' is not available"});
  }
  if (!plugins_.trackers.contains(request.controller)) {
    return done(api::DomainError{api::ErrorKind::kImpossible, "unsupported_controller",
                                 "the controller '" + request.controller + "' is not available"});
  }
  runtime_.post([this, request, done = std::move(done)](TickContext& context) mutable {
    if (stages_.mux.estop()) return done(estop_engaged());
    if (context.mapping) return done(mapping_active());
    // Planning takes milliseconds to tens of them: on the worker, never on the control loop.
    stages_.navigate.plan(
        request, context,
        [this, request, done = std::move(done)](PlanningWorker::Outcome outcome) mutable {
          start_planned(request, std::move(outcome), std::move(done));
        });
  });
}

void ControlService::start_planned(const api::GoalRequest& request, PlanningWorker::Outcome outcome,
                                   api::Completion<navigation::Goal> done) {
  if (outcome.error) return done(plan_error(*outcome.error));
  runtime_.post([this, request, path = std::move(outcome.path),
                 done = std::move(done)](TickContext& context) mutable {
    // The e-stop may have been engaged, or mapping started, while the plan was made.
    if (stages_.mux.estop()) return done(estop_engaged());
    if (context.mapping) return done(mapping_active());
    auto goal = stages_.navigate.start(request, path, context);
    if (!goal) {
      return done(api::DomainError{api::ErrorKind::kImpossible, "unsupported_controller",
                                   "the controller '" + request.controller + "' is not available"});
    }
    // The goal events (a preempted goal, this one starting) are in the run before the reply.
    after_commit(recorder_, context, std::move(done), std::move(*goal));
  });
}

std::vector<navigation::Goal> ControlService::list_goals() const {
  return *runtime_.state()->goals;
}

std::optional<navigation::Goal> ControlService::find_goal(std::int64_t id) const {
  for (const auto& goal : *runtime_.state()->goals) {
    if (goal.id == id) return goal;
  }
  return std::nullopt;
}

void ControlService::cancel_goal(std::int64_t id, api::Completion<navigation::Goal> done) {
  runtime_.post([this, id, done = std::move(done)](TickContext& context) mutable {
    const auto before = stages_.navigate.find(id);
    if (!before)
      return done(
          api::DomainError{api::ErrorKind::kNotFound, "unknown_goal", "no goal with this id"});
    if (before->finished()) {
      return done(api::DomainError{api::ErrorKind::kConflict, "goal_finished",
                                   "the goal has already ended (" +
                                       std::string(navigation::to_string(before->status)) + ")"});
    }
    stages_.navigate.cancel(id, context);
    after_commit(recorder_, context, std::move(done), *stages_.navigate.find(id));
  });
}

void ControlService::set_localization_pose(const geometry::Pose2D& pose,
                                           const std::array<double, 9>& covariance,
                                           api::Completion<api::Done> done) {
  runtime_.post([this, pose, covariance, done = std::move(done)](TickContext& context) mutable {
    if (context.mapping) return done(mapping_active());
    stages_.estimate.set_pose(pose, to_matrix(covariance), context);
    context.event("localization", {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}});
    after_commit(recorder_, context, std::move(done), api::Done{});
  });
}

}  // namespace mobot::server

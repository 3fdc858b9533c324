#include "core/navigation/goal_navigator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mobot::navigation {

GoalNavigator::GoalNavigator(GoalNavigatorOptions options)
    : options_(std::move(options)),
      supervisor_(options_.supervisor, options_.avoidance),
      avoider_(options_.avoidance) {}

Goal* GoalNavigator::active() {
  if (goals_.empty() || goals_.back().finished()) return nullptr;
  return &goals_.back();
}

std::optional<std::int64_t> GoalNavigator::active_id() const {
  if (goals_.empty() || goals_.back().finished()) return std::nullopt;
  return goals_.back().id;
}

const Goal& GoalNavigator::start(Goal goal, const planning::Path& path,
                                 std::unique_ptr<control::PathTracker> tracker, double now_s) {
  if (!tracker) throw std::invalid_argument("no tracker for controller '" + goal.controller + "'");
  end_active(GoalStatus::kCanceled, "preempted", now_s);
  tracker_ = std::move(tracker);
  goal.status = GoalStatus::kActive;
  goal.created_s = now_s;
  goals_.push_back(std::move(goal));
  while (goals_.size() > options_.history) goals_.pop_front();
  follow(goals_.back(), path, now_s);
  return goals_.back();
}

void GoalNavigator::follow(Goal& goal, const planning::Path& path, double now_s) {
  goal.path = path.points();
  const std::optional<double> heading =
      goal.has_heading ? std::optional<double>(goal.target.theta) : std::nullopt;
  tracker_->set_path(path, heading);
  supervisor_.set_path(path, now_s);
  avoider_.reset();
  replan_requested_ = false;
  last_moved_s_ = now_s;
  last_moved_pose_ = {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0};
  note_change(goal);
}

bool GoalNavigator::stuck(double now_s, const geometry::Pose2D& pose) {
  const bool moved = !(std::hypot(pose.x - last_moved_pose_.x, pose.y - last_moved_pose_.y) <
                       options_.stuck_distance_m) ||
                     std::abs(geometry::wrap_angle(pose.theta - last_moved_pose_.theta)) >
                         options_.stuck_angle_rad;
  if (moved) {
    last_moved_pose_ = pose;
    last_moved_s_ = now_s;
    return false;
  }
  return now_s - last_moved_s_ > options_.stuck_timeout_s;
}

void GoalNavigator::end_active(GoalStatus status, const std::string& reason, double now_s) {
  if (Goal* goal = active()) finish(*goal, status, reason, now_s);
}

bool GoalNavigator::cancel(std::int64_t id, double now_s) {
  const auto it =
      std::find_if(goals_.begin(), goals_.end(), [id](const Goal& goal) { return goal.id == id; });
  if (it == goals_.end()) return false;
  if (!it->finished()) finish(*it, GoalStatus::kCanceled, "canceled", now_s);
  return true;
}

void GoalNavigator::replan(std::int64_t id, const planning::Path& path, double now_s) {
  Goal* goal = active();
  if (goal == nullptr || goal->id != id) return;
  ++goal->replans;
  follow(*goal, path, now_s);
}

void GoalNavigator::finish(Goal& goal, GoalStatus status, const std::string& reason, double now_s) {
  goal.status = status;
  goal.reason = status == GoalStatus::kSucceeded ? "" : reason;
  goal.ended_s = now_s;
  if (tracker_) tracker_->clear();
  supervisor_.clear();
  replan_requested_ = false;
  note_change(goal);
}

void GoalNavigator::note_change(const Goal& goal) { changes_.push_back(goal); }

std::vector<Goal> GoalNavigator::take_changes() {
  std::vector<Goal> out;
  out.swap(changes_);
  return out;
}

GoalNavigator::TickResult GoalNavigator::tick(double now_s, const geometry::Pose2D& pose,
                                              const msgs::Twist& velocity,
                                              std::span<const msgs::RangeReading> sonar) {
  TickResult result;
  Goal* goal = active();
  if (goal == nullptr) return result;
  if (stuck(now_s, pose)) {
    finish(*goal, GoalStatus::kFailed, "stuck", now_s);
    return result;
  }
  const auto decision = supervisor_.update(now_s, pose, sonar);
  result.mode = decision.mode;
  result.command = msgs::Twist{};
  switch (decision.mode) {
    case control::NavigationMode::kTracking:
      result.command = tracker_->compute(pose, velocity, now_s);
      if (tracker_->arrived()) {
        finish(*goal, GoalStatus::kSucceeded, "", now_s);
        result.command = msgs::Twist{};
      }
      break;
    case control::NavigationMode::kAvoiding:
      if (decision.entered_avoidance) avoider_.reset();
      result.command = avoider_.compute(pose, decision.rejoin_point, sonar).command;
      break;
    case control::NavigationMode::kBlocked:
      if (replan_requested_) break;
      if (goal->replans >= options_.max_replans) {
        finish(*goal, GoalStatus::kFailed, "blocked", now_s);
      } else {
        replan_requested_ = true;
        result.replan_needed = true;
      }
      break;
    case control::NavigationMode::kIdle:
      break;
  }
  return result;
}

std::optional<Goal> GoalNavigator::find(std::int64_t id) const {
  for (const auto& goal : goals_) {
    if (goal.id == id) return goal;
  }
  return std::nullopt;
}

std::vector<Goal> GoalNavigator::list() const { return {goals_.begin(), goals_.end()}; }

}  // namespace mobot::navigation

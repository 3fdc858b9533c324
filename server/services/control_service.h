#pragma once

#include "api/ports/control_port.h"
#include "core/kinematics/kinematic_model.h"
#include "server/plugins/plugins.h"
#include "server/recorder.h"
#include "server/runtime.h"
#include "server/services/after_commit.h"
#include "server/stages/estimate_stage.h"
#include "server/stages/mux_stage.h"
#include "server/stages/navigate_stage.h"
#include "server/stages/write_base_stage.h"

namespace mobot::server {

// The stages a control command acts on.
struct ControlStages {
  MuxStage& mux;
  NavigateStage& navigate;
  EstimateStage& estimate;
  WriteBaseStage& write_base;
};

// The ControlPort: reads from the runtime's published state, commands posted to the control loop;
// a command that records an event completes once the event is on disk.
class ControlService final : public api::ControlPort {
 public:
  ControlService(Runtime& runtime, Recorder& recorder, ControlStages stages,
                 const kinematics::KinematicModel& kinematics, const ConfiguredPlugins& plugins,
                 NavigationSection defaults = {});

  api::RobotSnapshot snapshot() const override { return runtime_.state()->robot; }
  double time_s() const override { return runtime_.state()->robot.t_s; }
  void teleop(const msgs::Twist& command, int ttl_ms, api::Completion<msgs::Twist> done) override;
  void set_estop(bool engaged, api::Completion<bool> done) override;
  void submit_goal(const api::GoalRequest& request,
                   api::Completion<navigation::Goal> done) override;
  std::vector<navigation::Goal> list_goals() const override;
  std::optional<navigation::Goal> find_goal(std::int64_t id) const override;
  void cancel_goal(std::int64_t id, api::Completion<navigation::Goal> done) override;
  void set_localization_pose(const geometry::Pose2D& pose, const std::array<double, 9>& covariance,
                             api::Completion<api::Done> done) override;
  std::vector<std::string> planner_names() const override { return plugins_.planners.names(); }
  std::vector<std::string> controller_names() const override { return plugins_.trackers.names(); }
  std::string default_controller() const override { return defaults_.controller; }
  std::string default_planner() const override { return defaults_.planner; }

 private:
  void start_planned(const api::GoalRequest& request, PlanningWorker::Outcome outcome,
                     api::Completion<navigation::Goal> done);
  Runtime& runtime_;
  Recorder& recorder_;
  ControlStages stages_;
  const kinematics::KinematicModel& kinematics_;
  const ConfiguredPlugins& plugins_;
  const NavigationSection defaults_;
};

// The refusal a planning error is, in the contract's codes.
api::DomainError plan_error(planning::PlanError error);

}  // namespace mobot::server

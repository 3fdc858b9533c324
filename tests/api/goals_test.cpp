// Goal navigation: POST/GET/DELETE /api/v1/goals (lifecycle, 400/403/404/409/422, preemption,
// teleop override, e-stop), the `goal` and `path` stream topics, an obstacle dropped on the path,
// the EKF estimate against the simulator's truth while driving, and POST /api/v1/localization/pose.
// The office world (20 x 15 m, start (2, 7.5, 0) in a 2 m east-west corridor y 6.5..8.5).
#include <map>
#include <numbers>
#include <set>

#include "support/goal_support.h"

namespace mobot::testing {
namespace {

// Generous robot-time limits: a goal across the corridor takes ~30 s of robot time.
constexpr double kGoalTimeout_s = 120.0;

MobotdProcess::Options fast_clock() {
  MobotdProcess::Options options;
  options.time_scale = 20.0;
  return options;
}

class GoalsTest : public ServerSuite<GoalsTest> {
 public:
  static MobotdProcess::Options server_options() { return fast_clock(); }
  // For the scenario helpers outside the fixture.
  static HttpClient operator_client_for_scenario() { return operator_client(); }
  static HttpClient viewer_for_scenario() { return viewer(); }

 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
    // The robot back at (2, 7.5, 0); a running goal ends (reason `reset`).
    const HttpReply reset = operator_client().post("/api/v1/sim/reset", json::object());
    ASSERT_EQ(reset.status, 200) << reset.body;
  }
  void TearDown() override {
    operator_client().post("/api/v1/estop", json{{"engaged", false}});
    operator_client().post("/api/v1/sim/reset", json::object());
    ServerSuite::TearDown();
  }

  static json goals() {
    const HttpReply reply = viewer().get("/api/v1/goals");
    EXPECT_EQ(reply.status, 200) << reply.body;
    return reply.status == 200 ? reply.json() : json::array();
  }
  static json goal(std::int64_t id) {
    const HttpReply reply = viewer().get("/api/v1/goals/" + std::to_string(id));
    EXPECT_EQ(reply.status, 200) << reply.body;
    return reply.status == 200 ? reply.json() : json::object();
  }
  // POSTs a goal that must be accepted and returns its reply body.
  static json start_goal(double x, double y, double theta) {
    const HttpReply reply = post_goal(operator_client(), x, y, theta);
    EXPECT_EQ(reply.status, 201) << reply.body;
    return reply.status == 201 ? reply.json() : json{{"id", -1}};
  }
  // Waits until the robot has driven `distance` m (truth) from where it was.
  static bool wait_moved(double distance, double robot_timeout_s = 20.0) {
    const json from = sim_truth(viewer()).at("pose");
    const double t0 = robot_time(viewer());
    return wait_until(
               [&] {
                 return xy_distance(sim_truth(viewer()).at("pose"), from) >= distance ||
                        robot_time(viewer()) > t0 + robot_timeout_s;
               },
               30s) &&
           xy_distance(sim_truth(viewer()).at("pose"), from) >= distance;
  }
  // The list of (id, status) of GET /goals: what a refused request must leave unchanged.
  static std::vector<std::pair<std::int64_t, std::string>> goal_states() {
    std::vector<std::pair<std::int64_t, std::string>> out;
    for (const auto& g : goals()) out.emplace_back(g.at("id"), g.at("status"));
    return out;
  }
};

void expect_error(const HttpReply& reply, int status, const std::string& code,
                  const std::string& what) {
  EXPECT_EQ(reply.status, status) << what << ": " << reply.body;
  EXPECT_EQ(reply.error_code(), code) << what << ": " << reply.body;
}

// ----- lifecycle
// ----------------------------------------------------------------------------------

TEST_F(GoalsTest, PostStartsAGoalOnAPathFromTheRobotToTheTarget) {
  const json robot = robot_state(viewer());
  ASSERT_EQ(robot.at("mode"), "idle");
  const HttpReply reply = post_goal(operator_client(), 6.0, 7.5, 0.5);
  ASSERT_EQ(reply.status, 201) << reply.body;
  const json created = reply.json();
  ASSERT_TRUE(created.at("id").is_number_integer()) << reply.body;
  const std::int64_t id = created.at("id");
  EXPECT_GE(id, 1);
  EXPECT_EQ(created.at("status"), "active");
  EXPECT_FALSE(created.contains("reason")) << reply.body;
  EXPECT_FALSE(created.contains("ended_t")) << reply.body;
  EXPECT_DOUBLE_EQ(created.at("target").at("x").get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(created.at("target").at("y").get<double>(), 7.5);
  EXPECT_NEAR(created.at("target").at("theta").get<double>(), 0.5, 1e-12);
  EXPECT_TRUE(created.at("created_t").is_number());
  EXPECT_GE(created.at("created_t").get<double>(), robot.at("t").get<double>());
  const json& path = created.at("path");
  ASSERT_TRUE(path.is_array());
  ASSERT_GE(path.size(), 2U) << reply.body;
  for (const auto& point : path) {
    ASSERT_TRUE(point.is_array() && point.size() == 2U) << point.dump();
    ASSERT_TRUE(point[0].is_number() && point[1].is_number()) << point.dump();
  }
  const json first{{"x", path.front()[0]}, {"y", path.front()[1]}};
  const json last{{"x", path.back()[0]}, {"y", path.back()[1]}};
  EXPECT_LT(xy_distance(first, robot.at("pose")), 0.25) << "the path starts at " << first.dump();
  EXPECT_LT(xy_distance(last, json{{"x", 6.0}, {"y", 7.5}}), 0.05)
      << "the path ends at " << last.dump();

  // Listed, readable by id, and the robot is navigating.
  const json listed = goals();
  ASSERT_TRUE(listed.is_array());
  ASSERT_FALSE(listed.empty());
  bool found = false;
  for (const auto& g : listed) {
    if (g.at("id") == id) {
      found = true;
      EXPECT_EQ(g.at("target"), created.at("target"));
      EXPECT_EQ(g.at("path"), created.at("path"));
    }
  }
  EXPECT_TRUE(found) << listed.dump().substr(0, 400);
  const json read = goal(id);
  EXPECT_EQ(read.at("id"), id);
  EXPECT_EQ(read.at("target"), created.at("target"));
  EXPECT_EQ(read.at("created_t"), created.at("created_t"));
  // The mode while the goal is active (read before a status that is still `active`).
  const std::string mode = robot_state(viewer()).at("mode");
  if (goal(id).at("status") == "active") {
    EXPECT_EQ(mode, "navigating");
  }

  const json ended = wait_goal_end(viewer(), id, kGoalTimeout_s);
  ASSERT_EQ(ended.at("status"), "succeeded") << ended.dump();
  EXPECT_FALSE(ended.contains("reason")) << ended.dump();
  ASSERT_TRUE(ended.contains("ended_t")) << ended.dump();
  EXPECT_GE(ended.at("ended_t").get<double>(), ended.at("created_t").get<double>());
  const json truth = sim_truth(viewer());
  const json target{{"x", 6.0}, {"y", 7.5}, {"theta", 0.5}};
  EXPECT_LT(xy_distance(truth.at("pose"), target), 0.10) << pose_text(truth.at("pose"));
  EXPECT_LT(heading_error(truth.at("pose"), target), 0.10) << pose_text(truth.at("pose"));
  EXPECT_EQ(truth.at("collisions"), 0);
  ASSERT_TRUE(wait_robot_time(viewer(), 0.1));
  EXPECT_EQ(robot_state(viewer()).at("mode"), "idle");

  // The run recorded the goal's start and its end.
  const auto events = goal_events(viewer(), current_run_id(viewer()), id);
  ASSERT_GE(events.size(), 2U);
  EXPECT_EQ(events.front().at("detail").at("status"), "active");
  EXPECT_EQ(events.back().at("detail").at("status"), "succeeded");
}

TEST_F(GoalsTest, GoalWithoutHeadingHasNoTargetThetaAndSucceeds) {
  const HttpReply reply = operator_client().post("/api/v1/goals", json{{"x", 4.0}, {"y", 7.2}});
  ASSERT_EQ(reply.status, 201) << reply.body;
  const json created = reply.json();
  EXPECT_FALSE(created.at("target").contains("theta")) << reply.body;
  const json ended = wait_goal_end(viewer(), created.at("id"), kGoalTimeout_s);
  EXPECT_EQ(ended.at("status"), "succeeded") << ended.dump();
  const json truth = sim_truth(viewer());
  EXPECT_LT(xy_distance(truth.at("pose"), json{{"x", 4.0}, {"y", 7.2}}), 0.10)
      << pose_text(truth.at("pose"));
  EXPECT_EQ(truth.at("collisions"), 0);
}

TEST_F(GoalsTest, UnknownGoalsAre404) {
  for (const std::string id : {"999999", "0", "-1", "abc", "1.5"}) {
    expect_error(viewer().get("/api/v1/goals/" + id), 404, "unknown_goal", "GET " + id);
    expect_error(operator_client().del("/api/v1/goals/" + id), 404, "unknown_goal", "DELETE " + id);
  }
  EXPECT_EQ(viewer().get("/api/v1/goals/1/extra").status, 404);
  expect_error(operator_client().request("PUT", "/api/v1/goals", "{}"), 405, "method_not_allowed",
               "PUT /goals");
  expect_error(operator_client().request("POST", "/api/v1/goals/1", "{}"), 405,
               "method_not_allowed", "POST /goals/1");
}

TEST_F(GoalsTest, DeleteCancelsTheGoalAndTheRobotStops) {
  const json created = start_goal(16.0, 7.5, 0.0);
  const std::int64_t id = created.at("id");
  ASSERT_TRUE(wait_moved(1.0)) << "the robot did not drive toward the goal";
  EXPECT_GT(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.1);

  const HttpReply reply = operator_client().del("/api/v1/goals/" + std::to_string(id));
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.json().at("id"), id);
  EXPECT_EQ(reply.json().at("status"), "canceled");
  const json canceled = goal(id);
  EXPECT_EQ(canceled.at("status"), "canceled");
  EXPECT_EQ(canceled.value("reason", ""), "canceled") << canceled.dump();
  EXPECT_TRUE(canceled.contains("ended_t"));

  // The robot brakes to a standstill and stays there.
  ASSERT_TRUE(wait_robot_time(viewer(), 2.0));
  const json stopped = robot_state(viewer());
  EXPECT_NEAR(stopped.at("velocity").at("v").get<double>(), 0.0, 0.01) << stopped.dump();
  EXPECT_NEAR(stopped.at("velocity").at("w").get<double>(), 0.0, 0.01) << stopped.dump();
  EXPECT_EQ(stopped.at("mode"), "idle");
  const json truth = sim_truth(viewer());
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));
  EXPECT_LT(xy_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.005);

  expect_error(operator_client().del("/api/v1/goals/" + std::to_string(id)), 409, "goal_finished",
               "DELETE of a canceled goal");
  EXPECT_EQ(goal(id).at("status"), "canceled");
  const auto events = goal_events(viewer(), current_run_id(viewer()), id);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().at("detail").at("status"), "canceled");
  EXPECT_EQ(events.back().at("detail").value("reason", ""), "canceled");
}

TEST_F(GoalsTest, DeleteOfASucceededGoalIs409) {
  const json created = start_goal(3.0, 7.5, 0.0);
  const json ended = wait_goal_end(viewer(), created.at("id"), kGoalTimeout_s);
  ASSERT_EQ(ended.at("status"), "succeeded") << ended.dump();
  expect_error(operator_client().del("/api/v1/goals/" + std::to_string(ended.at("id").get<int>())),
               409, "goal_finished", "DELETE of a succeeded goal");
  EXPECT_EQ(goal(ended.at("id")).at("status"), "succeeded");
}

TEST_F(GoalsTest, ANewGoalPreemptsTheActiveOne) {
  const json first = start_goal(16.0, 7.5, 0.0);
  ASSERT_TRUE(wait_moved(0.5));
  const json second = start_goal(4.0, 7.5, std::numbers::pi);
  ASSERT_NE(first.at("id"), second.at("id"));
  EXPECT_EQ(second.at("status"), "active");
  const json preempted = goal(first.at("id"));
  EXPECT_EQ(preempted.at("status"), "canceled") << preempted.dump();
  EXPECT_EQ(preempted.value("reason", ""), "preempted") << preempted.dump();
  // Exactly one goal is active: the new one.
  int active = 0;
  for (const auto& g : goals()) {
    if (g.at("status") == "active") {
      ++active;
      EXPECT_EQ(g.at("id"), second.at("id"));
    }
  }
  EXPECT_EQ(active, 1);
  const json ended = wait_goal_end(viewer(), second.at("id"), kGoalTimeout_s);
  EXPECT_EQ(ended.at("status"), "succeeded") << ended.dump();
  const json truth = sim_truth(viewer());
  const json target{{"x", 4.0}, {"y", 7.5}, {"theta", std::numbers::pi}};
  EXPECT_LT(xy_distance(truth.at("pose"), target), 0.10) << pose_text(truth.at("pose"));
  EXPECT_LT(heading_error(truth.at("pose"), target), 0.10) << pose_text(truth.at("pose"));
  EXPECT_EQ(truth.at("collisions"), 0);
  const auto events = goal_events(viewer(), current_run_id(viewer()), first.at("id"));
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().at("detail").value("reason", ""), "preempted");
}

TEST_F(GoalsTest, TeleopCancelsTheGoal) {
  const json created = start_goal(16.0, 7.5, 0.0);
  ASSERT_TRUE(wait_moved(0.5));
  const double t_command = robot_time(viewer());
  const HttpReply teleop =
      operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}, {"ttl_ms", 1000}});
  ASSERT_EQ(teleop.status, 200) << teleop.body;
  const json canceled = goal(created.at("id"));
  EXPECT_EQ(canceled.at("status"), "canceled") << canceled.dump();
  EXPECT_EQ(canceled.value("reason", ""), "teleop_override") << canceled.dump();
  const json during = robot_state(viewer());
  if (during.at("t").get<double>() < t_command + 0.9) {  // well inside the 1 s ttl
    EXPECT_EQ(during.at("mode"), "teleop");
  }
  // The zero command holds: the robot stops and does not resume the goal afterwards.
  ASSERT_TRUE(wait_robot_time(viewer(), 2.5));
  const json stopped = robot_state(viewer());
  EXPECT_NEAR(stopped.at("velocity").at("v").get<double>(), 0.0, 0.01);
  EXPECT_EQ(stopped.at("mode"), "idle");
  EXPECT_EQ(goal(created.at("id")).at("status"), "canceled");
}

TEST_F(GoalsTest, TeleopOverTheStreamCancelsTheGoalToo) {
  WsClient stream(port(), operator_token());
  const json created = start_goal(16.0, 7.5, 0.0);
  ASSERT_TRUE(wait_moved(0.5));
  stream.send({{"op", "teleop"}, {"v", 0.0}, {"w", 0.0}});
  ASSERT_TRUE(stream.read_until("teleop", 5s).has_value());
  const json canceled = goal(created.at("id"));
  EXPECT_EQ(canceled.at("status"), "canceled") << canceled.dump();
  EXPECT_EQ(canceled.value("reason", ""), "teleop_override") << canceled.dump();
}

TEST_F(GoalsTest, EstopCancelsTheGoalAndRefusesNewOnes) {
  const json created = start_goal(16.0, 7.5, 0.0);
  ASSERT_TRUE(wait_moved(0.5));
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  const json canceled = goal(created.at("id"));
  EXPECT_EQ(canceled.at("status"), "canceled") << canceled.dump();
  EXPECT_EQ(canceled.value("reason", ""), "estop") << canceled.dump();
  EXPECT_EQ(robot_state(viewer()).at("mode"), "estop");

  const auto before = goal_states();
  expect_error(post_goal(operator_client(), 5.0, 7.5, 0.0), 409, "estop_engaged",
               "POST /goals under e-stop");
  EXPECT_EQ(goal_states(), before) << "a refused goal changed the goal list";
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));
  EXPECT_NEAR(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.0, 1e-3);

  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  const HttpReply after = post_goal(operator_client(), 5.0, 7.5, 0.0);
  EXPECT_EQ(after.status, 201) << after.body;
  EXPECT_EQ(goal(created.at("id")).at("status"), "canceled");
}

TEST_F(GoalsTest, OnlyOperatorsPostAndCancelGoals) {
  const auto before = goal_states();
  expect_error(post_goal(viewer(), 5.0, 7.5, 0.0), 403, "forbidden", "viewer POST");
  EXPECT_EQ(anonymous().post("/api/v1/goals", json{{"x", 5.0}, {"y", 7.5}}).status, 401);
  EXPECT_EQ(goal_states(), before);
  EXPECT_EQ(robot_state(viewer()).at("mode"), "idle");

  const json created = start_goal(16.0, 7.5, 0.0);
  const std::string target = "/api/v1/goals/" + std::to_string(created.at("id").get<int>());
  expect_error(viewer().del(target), 403, "forbidden", "viewer DELETE");
  EXPECT_EQ(anonymous().del(target).status, 401);
  EXPECT_EQ(goal(created.at("id")).at("status"), "active");
  EXPECT_EQ(viewer().get("/api/v1/goals").status, 200);
  EXPECT_EQ(anonymous().get("/api/v1/goals").status, 401);
  EXPECT_EQ(anonymous().get(target).status, 401);
  // Admin is above operator.
  EXPECT_EQ(admin().del(target).status, 200);
}

// ----- refused goals
// ------------------------------------------------------------------------------

TEST_F(GoalsTest, ImpossibleGoalsAre422AndChangeNothing) {
  const json running = start_goal(16.0, 7.5, 0.0);
  ASSERT_TRUE(wait_moved(0.3));
  const auto before = goal_states();
  struct Case {
    json body;
    std::string code;
  };
  const std::vector<Case> cases = {
      // In the corridor's south wall (y 6.35..6.5) and in the west outer wall (x 0..0.2).
      {{{"x", 5.0}, {"y", 6.42}}, "goal_in_obstacle"},
      {{{"x", 0.1}, {"y", 7.5}, {"theta", 0.0}}, "goal_in_obstacle"},
      // Free on the map but 0.15 m from the wall: the 0.6 m robot does not fit.
      {{{"x", 5.0}, {"y", 6.65}}, "goal_in_obstacle"},
      // In the north-south corridor's west wall.
      {{{"x", 8.93}, {"y", 4.0}}, "goal_in_obstacle"},
      // Outside the 20 x 15 m map.
      {{{"x", 25.0}, {"y", 7.5}}, "goal_outside_map"},
      {{{"x", -3.0}, {"y", 7.5}}, "goal_outside_map"},
      {{{"x", 10.0}, {"y", 20.0}}, "goal_outside_map"},
      {{{"x", 10.0}, {"y", -0.5}, {"theta", 1.0}}, "goal_outside_map"},
      {{{"x", 1e5}, {"y", -1e5}}, "goal_outside_map"},
      // Well-formed but not in this build.
      {{{"x", 5.0}, {"y", 6.65}, {"planner", "voronoi"}}, "goal_in_obstacle"},
      {{{"x", 5.0}, {"y", 7.5}, {"controller", "potential_field"}}, "unsupported_controller"},
  };
  for (const auto& test : cases) {
    const HttpReply reply = operator_client().post("/api/v1/goals", test.body);
    expect_error(reply, 422, test.code, test.body.dump());
    EXPECT_EQ(goal_states(), before) << "after " << test.body.dump();
  }
  // The first goal kept running all along, toward its own target.
  const json still = goal(running.at("id"));
  EXPECT_EQ(still.at("status"), "active") << still.dump();
  EXPECT_EQ(still.at("target"), running.at("target"));
  EXPECT_EQ(robot_state(viewer()).at("mode"), "navigating");
  EXPECT_TRUE(wait_moved(0.3)) << "the running goal stopped driving";
}

TEST_F(GoalsTest, MalformedGoalsAre400AndChangeNothing) {
  const json running = start_goal(16.0, 7.5, 0.0);
  const auto before = goal_states();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"x":NaN,"y":7.5})", "malformed_json"},
      {R"({"x":5,"y":Infinity})", "malformed_json"},
      {R"({"x":-Infinity,"y":7.5})", "malformed_json"},
      {R"({"x":1e999,"y":7.5})", "malformed_json"},
      {R"({"x":5,"y":7.5,"theta":NaN})", "malformed_json"},
      {R"({"y":7.5})", "missing_field"},
      {R"({"x":5})", "missing_field"},
      {R"({"x":null,"y":7.5})", "missing_field"},
      {R"({"x":"5","y":7.5})", "invalid_field"},
      {R"({"x":true,"y":7.5})", "invalid_field"},
      {R"({"x":5,"y":7.5,"theta":7.0})", "invalid_field"},
      {R"({"x":5,"y":7.5,"theta":-6.3})", "invalid_field"},
      {R"({"x":5,"y":7.5,"theta":"north"})", "invalid_field"},
      {R"({"x":2e6,"y":7.5})", "invalid_field"},
      {R"({"x":5,"y":7.5,"planner":"dijkstra"})", "invalid_field"},
      {R"({"x":5,"y":7.5,"planner":"ASTAR"})", "invalid_field"},
      {R"({"x":5,"y":7.5,"planner":""})", "invalid_field"},
      {R"({"x":5,"y":7.5,"planner":3})", "invalid_field"},
      {R"({"x":5,"y":7.5,"controller":"mpc"})", "invalid_field"},
      {R"([5,7.5])", "invalid_body"},
      {R"("goal")", "invalid_body"},
      {R"({"x":5,"y":7.5)", "malformed_json"},
      {"", "malformed_json"},
  };
  for (const auto& [body, code] : cases) {
    const HttpReply reply = operator_client().post("/api/v1/goals", body);
    EXPECT_EQ(reply.status, 400) << body << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), code) << body << ": " << reply.body;
    EXPECT_EQ(goal_states(), before) << "after " << body;
  }
  EXPECT_EQ(goal(running.at("id")).at("status"), "active");
  EXPECT_EQ(goal(running.at("id")).at("target"), running.at("target"));
}

// ----- stream ------------------------------------------------------------------------------------

TEST_F(GoalsTest, StreamDeliversTheGoalsStatusChangesAndItsPath) {
  WsClient stream(port(), viewer_token());
  stream.send({{"op", "subscribe"}, {"topics", {"goal", "path"}}});
  const auto subscribed = stream.read_until("subscribed", 5s);
  ASSERT_TRUE(subscribed.has_value()) << "no subscribed reply";
  ASSERT_EQ(subscribed->at("topics"), json({"goal", "path"})) << subscribed->dump();

  const json created = start_goal(4.5, 7.5, 0.0);
  const std::int64_t id = created.at("id");
  std::vector<json> goal_frames;
  std::vector<json> path_frames;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto frame = stream.read(2s);
    if (!frame) {
      if (!stream.is_open()) break;
      continue;
    }
    if (!frame->text()) continue;
    const json message = json::parse(frame->payload, nullptr, false);
    if (!message.is_object()) continue;
    if (message.value("topic", "") == "path") path_frames.push_back(message);
    if (message.value("topic", "") != "goal") continue;
    goal_frames.push_back(message);
    if (message.at("data").at("id") == id && goal_finished(message.at("data"))) break;
  }
  ASSERT_FALSE(goal_frames.empty()) << "no goal frame";
  for (const auto& frame : goal_frames) {
    EXPECT_TRUE(frame.at("t").is_number());
    EXPECT_EQ(frame.at("data").at("id"), id) << frame.dump().substr(0, 300);
  }
  EXPECT_EQ(goal_frames.front().at("data").at("status"), "active");
  EXPECT_EQ(goal_frames.front().at("data").at("target"), created.at("target"));
  EXPECT_EQ(goal_frames.back().at("data").at("status"), "succeeded")
      << goal_frames.back().dump().substr(0, 300);
  EXPECT_EQ(goal_frames.back().at("data").at("ended_t"), goal(id).at("ended_t"));
  // Status changes only: no repeats of the same status without a replan in between.
  for (std::size_t i = 1; i < goal_frames.size(); ++i) {
    EXPECT_GE(goal_frames[i].at("t").get<double>(), goal_frames[i - 1].at("t").get<double>());
  }

  ASSERT_FALSE(path_frames.empty()) << "no path frame";
  const json& path = path_frames.front();
  EXPECT_EQ(path.at("data").at("goal_id"), id) << path.dump().substr(0, 300);
  EXPECT_EQ(path.at("data").at("points"), created.at("path"));
  // The path came when the goal started.
  EXPECT_NEAR(path.at("t").get<double>(), created.at("created_t").get<double>(), 0.05);
  EXPECT_NEAR(path.at("t").get<double>(), goal_frames.front().at("t").get<double>(), 0.05);
}

TEST_F(GoalsTest, StreamCarriesCancelAndPreemptReasons) {
  WsClient stream(port(), viewer_token());
  stream.send({{"op", "subscribe"}, {"topics", {"goal"}}});
  ASSERT_TRUE(stream.read_until("subscribed", 5s).has_value());
  const json first = start_goal(16.0, 7.5, 0.0);
  const json second = start_goal(15.0, 7.5, 0.0);
  ASSERT_EQ(
      operator_client().del("/api/v1/goals/" + std::to_string(second.at("id").get<int>())).status,
      200);
  std::map<std::int64_t, std::vector<json>> by_goal;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < deadline &&
         !(by_goal[second.at("id")].size() >= 2U && by_goal[first.at("id")].size() >= 2U)) {
    const auto message = stream.read_until("goal", 2s);
    if (!message) continue;
    by_goal[message->at("data").at("id")].push_back(message->at("data"));
  }
  const auto& a = by_goal[first.at("id")];
  const auto& b = by_goal[second.at("id")];
  ASSERT_GE(a.size(), 2U);
  ASSERT_GE(b.size(), 2U);
  EXPECT_EQ(a.front().at("status"), "active");
  EXPECT_EQ(a.back().at("status"), "canceled");
  EXPECT_EQ(a.back().value("reason", ""), "preempted");
  EXPECT_EQ(b.front().at("status"), "active");
  EXPECT_EQ(b.back().at("status"), "canceled");
  EXPECT_EQ(b.back().value("reason", ""), "canceled");
}

// ----- obstacles and localization while driving
// ---------------------------------------------------

// Drives from `start` to `target` (heading 0, a straight path along y = start.y) and drops a
// 0.5 m wide, 1 m tall post on the path once the robot has driven 0.5 m: the goal must still
// succeed, without a collision, ending where it was sent.
void obstacle_scenario(const json& start, double target_x, double obstacle_x) {
  const double y = start.at("y").get<double>();
  const HttpClient op = GoalsTest::operator_client_for_scenario();
  const HttpClient view = GoalsTest::viewer_for_scenario();
  const HttpReply reset = op.post("/api/v1/sim/reset", json{{"pose", start}});
  ASSERT_EQ(reset.status, 200) << reset.body;
  const HttpReply reply = post_goal(op, target_x, y, 0.0);
  ASSERT_EQ(reply.status, 201) << reply.body;
  const json created = reply.json();
  const std::int64_t id = created.at("id");
  for (const auto& point : created.at("path")) {
    ASSERT_NEAR(point[1].get<double>(), y, 0.3) << "the path is not straight";
  }
  const json from = sim_truth(view).at("pose");
  ASSERT_TRUE(
      wait_until([&] { return xy_distance(sim_truth(view).at("pose"), from) >= 0.5; }, 30s));
  ASSERT_EQ(view.get("/api/v1/goals/" + std::to_string(id)).json().at("status"), "active");
  const json post{{"x", obstacle_x}, {"y", y}};
  const HttpReply obstacle =
      op.post("/api/v1/sim/obstacles",
              json{{"x", obstacle_x}, {"y", y}, {"radius", 0.25}, {"height", 1.0}});
  ASSERT_EQ(obstacle.status, 201) << obstacle.body;

  double closest = 1e9;
  const double t0 = robot_time(view);
  json ended;
  ASSERT_TRUE(wait_until(
      [&] {
        const json truth = sim_truth(view);
        closest = std::min(closest, xy_distance(truth.at("pose"), post));
        ended = view.get("/api/v1/goals/" + std::to_string(id)).json();
        return goal_finished(ended) || truth.at("t").get<double>() > t0 + kGoalTimeout_s;
      },
      180s, 10ms));
  const json truth = sim_truth(view);
  std::cout << "[ info ] obstacle at " << pose_text(post) << ": goal " << ended.value("status", "?")
            << " reason " << ended.value("reason", "-") << ", replans "
            << ended.value("replans", -1)
            << ", closest approach of the robot centre to the post centre " << closest
            << " m, final truth " << pose_text(truth.at("pose")) << ", collisions "
            << truth.at("collisions") << "\n";
  EXPECT_EQ(ended.at("status"), "succeeded") << ended.dump().substr(0, 300);
  EXPECT_EQ(truth.at("collisions"), 0);
  const json target{{"x", target_x}, {"y", y}, {"theta", 0.0}};
  EXPECT_LT(xy_distance(truth.at("pose"), target), 0.10);
  EXPECT_LT(heading_error(truth.at("pose"), target), 0.10);
  // It went around the post (0.25 m radius + 0.3 m half-width), not through it.
  EXPECT_GT(closest, 0.55);
  if (::testing::Test::HasFailure()) {
    for (const auto& event : run_events(view, current_run_id(view))) {
      if (event.at("t").get<double>() >= created.at("created_t").get<double>()) {
        std::cout << "  event " << event.dump() << "\n";
      }
    }
  }
}

// In the 2 m corridor (y 6.5..8.5): a post on its centre line leaves 0.75 m on either side for
// the 0.6 m wide robot.
TEST_F(GoalsTest, AnObstacleDroppedOnThePathInTheCorridorIsAvoided) {
  obstacle_scenario(json{{"x", 2.0}, {"y", 7.5}, {"theta", 0.0}}, 12.0, 7.0);
}

// In room N1 (x 0.2..6.85, y 8.65..14.8): open space on both sides of the post.
TEST_F(GoalsTest, AnObstacleDroppedOnThePathInARoomIsAvoided) {
  obstacle_scenario(json{{"x", 1.0}, {"y", 11.5}, {"theta", 0.0}}, 6.0, 3.5);
}

// The EKF estimate (pose topic) against the simulator's truth (truth topic) at the same ticks,
// over a goal that leaves the corridor through a door into a room.
TEST_F(GoalsTest, EstimateStaysCloseToTheTruthWhileDriving) {
  WsClient stream(port(), viewer_token());
  stream.send({{"op", "subscribe"}, {"topics", {"pose", "truth", "goal"}}});
  ASSERT_TRUE(stream.read_until("subscribed", 5s).has_value());
  const json created = start_goal(10.0, 11.5, std::numbers::pi / 2);
  const std::int64_t id = created.at("id");
  std::map<double, json> poses;
  std::map<double, json> truths;
  bool ended = false;
  json last_goal;
  const auto deadline = std::chrono::steady_clock::now() + 90s;
  while (!ended && std::chrono::steady_clock::now() < deadline) {
    const auto frame = stream.read(2s);
    if (!frame) {
      if (!stream.is_open()) break;
      continue;
    }
    if (!frame->text()) continue;
    const json message = json::parse(frame->payload, nullptr, false);
    if (!message.is_object() || !message.contains("topic")) continue;
    const std::string topic = message.at("topic");
    const double t = message.at("t");
    if (topic == "pose") poses[t] = message.at("data");
    if (topic == "truth") truths[t] = message.at("data").at("pose");
    if (topic == "goal" && message.at("data").at("id") == id) {
      last_goal = message.at("data");
      ended = goal_finished(last_goal);
    }
  }
  ASSERT_TRUE(ended) << "the goal did not end: " << goal(id).dump().substr(0, 300);
  EXPECT_EQ(last_goal.at("status"), "succeeded") << last_goal.dump().substr(0, 300);
  int pairs = 0;
  double worst = 0.0;
  double worst_heading = 0.0;
  double worst_t = 0.0;
  for (const auto& [t, pose] : poses) {
    const auto truth = truths.find(t);
    if (truth == truths.end()) continue;
    ++pairs;
    const double error = xy_distance(pose, truth->second);
    worst_heading = std::max(worst_heading, heading_error(pose, truth->second));
    if (error > worst) {
      worst = error;
      worst_t = t;
    }
  }
  std::cout << "[ info ] estimate vs truth over " << pairs << " ticks: worst " << worst
            << " m at t " << worst_t << ", worst heading " << worst_heading << " rad\n";
  EXPECT_GE(pairs, 50) << "too few ticks with both a pose and a truth frame";
  EXPECT_LT(worst, 0.10);
  EXPECT_LT(worst_heading, 0.10);
  // A few REST samples too (the estimate and truth read back to back while standing at the end).
  const json robot = robot_state(viewer());
  const json truth = sim_truth(viewer());
  EXPECT_LT(xy_distance(robot.at("pose"), truth.at("pose")), 0.10);
  EXPECT_EQ(truth.at("collisions"), 0);
}

// ----- a map with an enclosed room: no_path ------------------------------------------------------

class GoalsMapTest : public ServerSuite<GoalsMapTest> {
 public:
  static MobotdProcess::Options server_options() { return fast_clock(); }

 protected:
  void TearDown() override {
    if (office_id_ > 0) {
      admin().post("/api/v1/maps/" + std::to_string(office_id_) + "/activate", "");
    }
    ServerSuite::TearDown();
  }
  std::int64_t office_id_ = -1;
};

// A 20 x 15 m map at 0.1 m (origin (0, 0): the office's frame) with a border and a closed box
// x 14..18, y 2..5 (0.2 m walls), free everywhere else.
std::vector<std::uint8_t> boxed_map_pixels() {
  constexpr int kWidth = 200;
  constexpr int kHeight = 150;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(kWidth) * kHeight, 254);
  auto set = [&](double x0, double y0, double x1, double y1) {
    for (int row = 0; row < kHeight; ++row) {
      const double y = (kHeight - 1 - row + 0.5) * 0.1;
      for (int col = 0; col < kWidth; ++col) {
        const double x = (col + 0.5) * 0.1;
        if (x >= x0 && x < x1 && y >= y0 && y < y1) {
          pixels[static_cast<std::size_t>(row) * kWidth + col] = 0;
        }
      }
    }
  };
  set(0.0, 0.0, 20.0, 0.2);
  set(0.0, 14.8, 20.0, 15.0);
  set(0.0, 0.0, 0.2, 15.0);
  set(19.8, 0.0, 20.0, 15.0);
  set(14.0, 2.0, 18.0, 2.2);
  set(14.0, 4.8, 18.0, 5.0);
  set(14.0, 2.0, 14.2, 5.0);
  set(17.8, 2.0, 18.0, 5.0);
  return pixels;
}

TEST_F(GoalsMapTest, AGoalInAnEnclosedRoomIs422NoPath) {
  office_id_ = active_map_id(viewer());
  ASSERT_GT(office_id_, 0);
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  // A goal on the office map; activating another map ends it.
  const HttpReply running = post_goal(operator_client(), 16.0, 7.5, 0.0);
  ASSERT_EQ(running.status, 201) << running.body;
  const std::int64_t running_id = running.json().at("id");

  json body{{"name", "boxed"},
            {"resolution", 0.1},
            {"origin", {{"x", 0.0}, {"y", 0.0}, {"theta", 0.0}}},
            {"image_base64", base64_encode(make_pgm(200, 150, boxed_map_pixels()))}};
  const HttpReply imported = admin().post("/api/v1/maps", body);
  ASSERT_EQ(imported.status, 201) << imported.body;
  const std::int64_t boxed = imported.json().at("id");
  const HttpReply activated =
      operator_client().post("/api/v1/maps/" + std::to_string(boxed) + "/activate", "");
  ASSERT_EQ(activated.status, 200) << activated.body;
  const HttpReply after = viewer().get("/api/v1/goals/" + std::to_string(running_id));
  ASSERT_EQ(after.status, 200);
  EXPECT_EQ(after.json().at("status"), "canceled") << after.body;
  EXPECT_EQ(after.json().value("reason", ""), "map_changed") << after.body;

  // A goal that keeps running while the refused ones come.
  const HttpReply second = post_goal(operator_client(), 10.0, 10.0, 0.0);
  ASSERT_EQ(second.status, 201) << second.body;
  const json before = viewer().get("/api/v1/goals").json();
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{16.0, 3.5}, {15.0, 2.8}}) {
    const HttpReply refused = post_goal(operator_client(), x, y, 0.0);
    expect_error(refused, 422, "no_path", "goal in the closed box at " + std::to_string(x));
  }
  // In the box's wall, outside the map: still their own codes on this map.
  expect_error(post_goal(operator_client(), 16.0, 2.1, 0.0), 422, "goal_in_obstacle", "box wall");
  expect_error(post_goal(operator_client(), 21.0, 3.0, 0.0), 422, "goal_outside_map", "outside");
  const json unchanged = viewer().get("/api/v1/goals").json();
  ASSERT_EQ(unchanged.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(unchanged[i].at("id"), before[i].at("id"));
    EXPECT_EQ(unchanged[i].at("status"), before[i].at("status"));
  }
  EXPECT_EQ(viewer()
                .get("/api/v1/goals/" + std::to_string(second.json().at("id").get<int>()))
                .json()
                .at("status"),
            "active");
}

// ----- localization ------------------------------------------------------------------------------

class LocalizationTest : public ServerSuite<LocalizationTest> {
 public:
  static MobotdProcess::Options server_options() { return fast_clock(); }

 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
    ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  }
  void TearDown() override {
    operator_client().post("/api/v1/sim/reset", json::object());
    ServerSuite::TearDown();
  }
};

json diagonal_cov(double xx, double yy, double tt) {
  return json::array({xx, 0.0, 0.0, 0.0, yy, 0.0, 0.0, 0.0, tt});
}

TEST_F(LocalizationTest, SetPoseReinitialisesTheEstimate) {
  const std::int64_t run = current_run_id(viewer());
  // 1 m and 0.5 rad away from the truth (2, 7.5, 0), with a tight covariance: the estimate jumps
  // there and the sensors do not drag it back within a few ticks.
  const json body{{"x", 3.0}, {"y", 8.0}, {"theta", 0.5}, {"cov", diagonal_cov(1e-6, 2e-6, 3e-6)}};
  const HttpReply reply = operator_client().post("/api/v1/localization/pose", body);
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json echoed = reply.json();
  EXPECT_DOUBLE_EQ(echoed.at("pose").at("x").get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(echoed.at("pose").at("y").get<double>(), 8.0);
  EXPECT_DOUBLE_EQ(echoed.at("pose").at("theta").get<double>(), 0.5);
  EXPECT_EQ(echoed.at("cov"), body.at("cov"));

  const json robot = robot_state(viewer());
  EXPECT_LT(xy_distance(robot.at("pose"), body), 0.03) << pose_text(robot.at("pose"));
  EXPECT_LT(heading_error(robot.at("pose"), body), 0.03) << pose_text(robot.at("pose"));
  const json& cov = robot.at("localization").at("cov");
  ASSERT_EQ(cov.size(), 9U);
  // Updates only shrink a covariance and standing still adds no process noise.
  EXPECT_GT(cov[0].get<double>(), 0.0);
  EXPECT_LE(cov[0].get<double>(), 1e-6 * 1.001) << cov.dump();
  EXPECT_GT(cov[4].get<double>(), 0.0);
  EXPECT_LE(cov[4].get<double>(), 2e-6 * 1.001) << cov.dump();
  EXPECT_GT(cov[8].get<double>(), 0.0);
  EXPECT_LE(cov[8].get<double>(), 3e-6 * 1.001) << cov.dump();
  // The simulator's robot did not move.
  const json truth = sim_truth(viewer());
  EXPECT_LT(xy_distance(truth.at("pose"), json{{"x", 2.0}, {"y", 7.5}}), 0.01);

  const json event = find_event(viewer(), run, "localization");
  ASSERT_FALSE(event.is_null()) << "no localization event";
  ASSERT_TRUE(event.at("detail").is_object() || event.at("detail").is_string()) << event.dump();
  const json detail = event.at("detail").is_string()
                          ? json::parse(event.at("detail").get<std::string>(), nullptr, false)
                          : event.at("detail");
  EXPECT_DOUBLE_EQ(detail.value("x", 0.0), 3.0) << event.dump();
  EXPECT_DOUBLE_EQ(detail.value("y", 0.0), 8.0) << event.dump();
}

// C7's workflow from a pose 0.15 m off: about the thickness of the inner wall beside the corridor,
// so matching a scan line to the wall's far face would fit the offset exactly. The map faces know
// their free side, and the far face cannot be seen from the robot's side.
TEST_F(LocalizationTest, ARoughPoseIsRefinedByTheSensors) {
  // C7's workflow: a rough initial pose (default covariance: 0.25 m, 0.1 rad), then drive.
  // At 20x a laser scan comes every 5 ms of wall time and its lines shrink the covariance below
  // 1e-4 within two scans: the re-initialised covariance is read back at the real-time rate.
  ASSERT_EQ(operator_client().put("/api/v1/sim/clock", json{{"time_scale", 1.0}}).status, 200);
  const json body{{"x", 2.15}, {"y", 7.4}, {"theta", 0.05}};
  const HttpReply reply = operator_client().post("/api/v1/localization/pose", body);
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json cov = reply.json().at("cov");
  ASSERT_EQ(cov.size(), 9U);
  EXPECT_NEAR(cov[0].get<double>(), 0.0625, 1e-12);
  EXPECT_NEAR(cov[4].get<double>(), 0.0625, 1e-12);
  EXPECT_NEAR(cov[8].get<double>(), 0.01, 1e-12);
  const json robot = robot_state(viewer());
  EXPECT_LE(robot.at("localization").at("cov")[0].get<double>(), 0.0625 * 1.001);
  EXPECT_GT(robot.at("localization").at("cov")[0].get<double>(), 1e-4)
      << "the covariance was not re-initialised";
  ASSERT_EQ(operator_client().put("/api/v1/sim/clock", json{{"time_scale", 20.0}}).status, 200);

  const HttpReply goal = post_goal(operator_client(), 6.0, 7.5, 0.0);
  ASSERT_EQ(goal.status, 201) << goal.body;
  const json ended = wait_goal_end(viewer(), goal.json().at("id"), kGoalTimeout_s);
  EXPECT_EQ(ended.at("status"), "succeeded") << ended.dump().substr(0, 300);
  const json estimate = robot_state(viewer());
  const json truth = sim_truth(viewer());
  std::cout << "[ info ] after the drive: estimate " << pose_text(estimate.at("pose")) << " truth "
            << pose_text(truth.at("pose")) << " cov diag "
            << estimate.at("localization").at("cov")[0] << ", "
            << estimate.at("localization").at("cov")[4] << ", "
            << estimate.at("localization").at("cov")[8] << "\n";
  EXPECT_LT(xy_distance(estimate.at("pose"), truth.at("pose")), 0.10);
  EXPECT_LT(heading_error(estimate.at("pose"), truth.at("pose")), 0.05);
  EXPECT_LT(estimate.at("localization").at("cov")[0].get<double>(), 0.0625);
}

// The number of `localization` events in a run.
std::size_t localization_events(const HttpClient& client, std::int64_t run) {
  std::size_t count = 0;
  for (const auto& event : run_events(client, run))
    count += event.value("kind", "") == "localization";
  return count;
}

TEST_F(LocalizationTest, BadPosesAndCovariancesAre400AndChangeNothing) {
  const std::int64_t run = current_run_id(viewer());
  const std::size_t events_before = localization_events(viewer(), run);
  const json before = robot_state(viewer());
  const std::vector<std::string> bodies = {
      // Asymmetric, 8 and 10 numbers, a negative variance, NaN, a string, not an array.
      R"({"x":3,"y":8,"theta":0,"cov":[1,0.5,0,0,1,0,0,0,1]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,1,0,0,0]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,1,0,0,0,1,0]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,-1,0,0,0,1]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,1,0,0,0,NaN]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,1,0,0,0,1e999]})",
      R"({"x":3,"y":8,"theta":0,"cov":[1,0,0,0,"1",0,0,0,1]})",
      R"({"x":3,"y":8,"theta":0,"cov":{"xx":1}})",
      R"({"x":3,"y":8,"theta":0,"cov":[[1,0,0],[0,1,0],[0,0,1]]})",
      R"({"x":3,"y":8,"theta":0,"cov":[]})",
      // The pose itself: theta is required here, finite, in range.
      R"({"x":3,"y":8})",
      R"({"x":3,"theta":0})",
      R"({"x":NaN,"y":8,"theta":0})",
      R"({"x":3,"y":8,"theta":Infinity})",
      R"({"x":3,"y":8,"theta":7})",
      R"({"x":"3","y":8,"theta":0})",
      R"([3,8,0])",
      "",
  };
  for (const auto& body : bodies) {
    const HttpReply reply = operator_client().post("/api/v1/localization/pose", body);
    EXPECT_EQ(reply.status, 400) << body << ": " << reply.body;
    EXPECT_FALSE(reply.error_code().empty()) << body << ": " << reply.body;
  }
  const json after = robot_state(viewer());
  EXPECT_LT(xy_distance(after.at("pose"), before.at("pose")), 0.01) << pose_text(after.at("pose"));
  EXPECT_LT(heading_error(after.at("pose"), before.at("pose")), 0.01);
  EXPECT_LE(after.at("localization").at("cov")[0].get<double>(),
            before.at("localization").at("cov")[0].get<double>() + 1e-9);
  EXPECT_EQ(localization_events(viewer(), run), events_before) << "a refused pose was recorded";
}

TEST_F(LocalizationTest, OnlyOperatorsSetThePose) {
  const json before = robot_state(viewer());
  const json body{{"x", 3.0}, {"y", 8.0}, {"theta", 0.0}};
  expect_error(viewer().post("/api/v1/localization/pose", body), 403, "forbidden", "viewer");
  EXPECT_EQ(anonymous().post("/api/v1/localization/pose", body).status, 401);
  EXPECT_LT(xy_distance(robot_state(viewer()).at("pose"), before.at("pose")), 0.01);
  expect_error(operator_client().get("/api/v1/localization/pose"), 405, "method_not_allowed",
               "GET pose");
  EXPECT_EQ(operator_client().post("/api/v1/localization/other", body).status, 404);
  EXPECT_EQ(operator_client().post("/api/v1/localization", body).status, 404);
  // Admin is above operator.
  EXPECT_EQ(admin()
                .post("/api/v1/localization/pose", json{{"x", 2.0}, {"y", 7.5}, {"theta", 0.0}})
                .status,
            200);
}

}  // namespace
}  // namespace mobot::testing

// Teleop (clamping, motion, dead-man), e-stop and the robot's mode.
#include "support/api_test.h"

namespace mobot::testing {
namespace {

class TeleopEstopTest : public ServerSuite<TeleopEstopTest> {
 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
    // Every test starts at the office start pose (2, 7.5, 0), facing 17 m of free corridor.
    const HttpReply reset = operator_client().post("/api/v1/sim/reset", json::object());
    ASSERT_EQ(reset.status, 200) << reset.body;
  }
  void TearDown() override {
    operator_client().post("/api/v1/estop", json{{"engaged", false}});
    ServerSuite::TearDown();
  }
};

double pose_distance(const json& a, const json& b) {
  return std::hypot(a.at("x").get<double>() - b.at("x").get<double>(),
                    a.at("y").get<double>() - b.at("y").get<double>());
}

TEST_F(TeleopEstopTest, ReplyIsClampedToTheRobotLimits) {
  HttpReply reply =
      operator_client().post("/api/v1/teleop", json{{"v", 5.0}, {"w", -9.0}, {"ttl_ms", 50}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_DOUBLE_EQ(reply.json().at("v").get<double>(), 1.3);
  EXPECT_DOUBLE_EQ(reply.json().at("w").get<double>(), -2.0);

  reply =
      operator_client().post("/api/v1/teleop", json{{"v", -100.0}, {"w", 100.0}, {"ttl_ms", 50}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_DOUBLE_EQ(reply.json().at("v").get<double>(), -1.3);
  EXPECT_DOUBLE_EQ(reply.json().at("w").get<double>(), 2.0);

  reply = operator_client().post("/api/v1/teleop", json{{"v", 0.25}, {"w", -0.5}, {"ttl_ms", 50}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_DOUBLE_EQ(reply.json().at("v").get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(reply.json().at("w").get<double>(), -0.5);
  EXPECT_EQ(reply.json().size(), 2U) << reply.body;
}

TEST_F(TeleopEstopTest, TeleopMovesTheRobot) {
  const json start = robot_state(viewer());
  const json truth_start = sim_truth(viewer());
  ASSERT_EQ(start.at("mode"), "idle");
  bool saw_teleop_mode = false;
  double max_v = 0.0;
  drive_for(operator_client(), 0.5, 0.0, 1.5, [&] {
    const json state = robot_state(viewer());
    saw_teleop_mode = saw_teleop_mode || state.at("mode") == "teleop";
    max_v = std::max(max_v, state.at("velocity").at("v").get<double>());
    return false;
  });
  const json end = robot_state(viewer());
  const json truth_end = sim_truth(viewer());
  EXPECT_TRUE(saw_teleop_mode);
  EXPECT_GT(max_v, 0.3);
  EXPECT_LT(max_v, 0.6);
  // 1.5 s at up to 0.5 m/s with 1 m/s^2 of acceleration: about 0.6 m east.
  const double dx = end.at("pose").at("x").get<double>() - start.at("pose").at("x").get<double>();
  EXPECT_GT(dx, 0.35);
  EXPECT_LT(dx, 1.2);
  EXPECT_NEAR(end.at("pose").at("y").get<double>(), start.at("pose").at("y").get<double>(), 0.1);
  const double true_dx =
      truth_end.at("pose").at("x").get<double>() - truth_start.at("pose").at("x").get<double>();
  EXPECT_GT(true_dx, 0.35);
  // The estimate follows the truth (odometry over a short straight run).
  EXPECT_LT(pose_distance(end.at("pose"), truth_end.at("pose")), 0.1);
}

TEST_F(TeleopEstopTest, TurningChangesTheHeading) {
  const double theta0 = robot_state(viewer()).at("pose").at("theta").get<double>();
  drive_for(operator_client(), 0.0, 1.0, 1.0);
  const double theta1 = robot_state(viewer()).at("pose").at("theta").get<double>();
  EXPECT_GT(theta1 - theta0, 0.3);  // counter-clockwise for w > 0
}

TEST_F(TeleopEstopTest, DeadManStopsTheRobotAndRecordsATimeout) {
  const std::int64_t run = current_run_id(viewer());
  const double t_start = robot_time(viewer());
  drive_for(operator_client(), 0.5, 0.0, 1.0);
  ASSERT_GT(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.2);
  // No more commands: after the 300 ms ttl and the braking the robot stands still.
  ASSERT_TRUE(wait_robot_time(viewer(), 1.5));
  const json stopped = robot_state(viewer());
  EXPECT_NEAR(stopped.at("velocity").at("v").get<double>(), 0.0, 0.01);
  EXPECT_NEAR(stopped.at("velocity").at("w").get<double>(), 0.0, 0.01);
  EXPECT_EQ(stopped.at("mode"), "idle");
  const json truth = sim_truth(viewer());
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  EXPECT_LT(pose_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.005);

  const json event = find_event(viewer(), run, "teleop_timeout");
  ASSERT_FALSE(event.is_null()) << "no teleop_timeout event";
  EXPECT_GE(event.at("t").get<double>(), t_start);
  EXPECT_LE(event.at("t").get<double>(), stopped.at("t").get<double>());
}

TEST_F(TeleopEstopTest, DeadManHonoursTheTtl) {
  const HttpReply reply =
      operator_client().post("/api/v1/teleop", json{{"v", 0.5}, {"w", 0.0}, {"ttl_ms", 1000}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  const double t0 = robot_time(viewer());
  // Well inside the ttl the robot is still driving...
  json inside;
  ASSERT_TRUE(wait_until([&] {
    inside = robot_state(viewer());
    return inside.at("t").get<double>() >= t0 + 0.6;
  }));
  if (inside.at("t").get<double>() < t0 + 0.9) {
    EXPECT_GT(inside.at("velocity").at("v").get<double>(), 0.3) << inside.dump();
    EXPECT_EQ(inside.at("mode"), "teleop");
  }
  // ...and well after it (1 s ttl + 0.5 s of braking) it has stopped.
  ASSERT_TRUE(wait_until([&] { return robot_time(viewer()) >= t0 + 2.2; }));
  EXPECT_NEAR(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.0, 0.01);
}

TEST_F(TeleopEstopTest, DefaultTtlIs300Milliseconds) {
  const double before = robot_time(viewer());
  ASSERT_EQ(operator_client().post("/api/v1/teleop", json{{"v", 0.3}, {"w", 0.0}}).status, 200);
  const double after = robot_time(viewer());
  // The command was taken between `before` and `after`: it holds until at least before + 0.3 and
  // is gone after after + 0.3 (plus a control period).
  int checked_inside = 0;
  bool checked_outside = false;
  ASSERT_TRUE(wait_until(
      [&] {
        const json state = robot_state(viewer());
        const double t = state.at("t").get<double>();
        if (t <= before + 0.28) {
          EXPECT_EQ(state.at("mode"), "teleop") << "at " << t - before << " s after the command";
          ++checked_inside;
        } else if (t >= after + 0.34) {
          EXPECT_EQ(state.at("mode"), "idle") << "at " << t - after << " s after the command";
          checked_outside = true;
        }
        return checked_outside;
      },
      30s, 1ms));
  EXPECT_GT(checked_inside, 0) << "the robot clock ran past the ttl before the first check";
}

TEST_F(TeleopEstopTest, ZeroCommandStopsTheRobot) {
  drive_for(operator_client(), 0.8, 0.0, 1.0);
  ASSERT_EQ(
      operator_client().post("/api/v1/teleop", json{{"v", 0}, {"w", 0}, {"ttl_ms", 1000}}).status,
      200);
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));
  EXPECT_NEAR(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.0, 0.01);
}

TEST_F(TeleopEstopTest, InvalidTeleopIsRefusedAndChangesNothing) {
  const json truth = sim_truth(viewer());
  const std::vector<std::string> bodies = {
      "",
      "{",
      "not json",
      "[]",
      "[0.5, 0]",
      "null",
      "0.5",
      R"({"v": NaN, "w": 0})",
      R"({"v": nan, "w": 0})",
      R"({"v": Infinity, "w": 0})",
      R"({"v": -Infinity, "w": 0})",
      R"({"v": "0.5", "w": 0})",
      R"({"v": true, "w": 0})",
      R"({"v": [0.5], "w": 0})",
      R"({"v": {"x": 1}, "w": 0})",
      R"({"v": null, "w": 0})",
      R"({"v": 0.5})",
      R"({"w": 0.5})",
      R"({})",
      R"({"V": 0.5, "W": 0})",
      R"({"v": 100.5, "w": 0})",
      R"({"v": 0, "w": -101})",
      R"({"v": 1e300, "w": 0})",
      R"({"v": 0.5, "w": 0, "ttl_ms": 10})",
      R"({"v": 0.5, "w": 0, "ttl_ms": 49})",
      R"({"v": 0.5, "w": 0, "ttl_ms": 1001})",
      R"({"v": 0.5, "w": 0, "ttl_ms": -300})",
      R"({"v": 0.5, "w": 0, "ttl_ms": "300"})",
      R"({"v": 0.5, "w": 0, "ttl_ms": NaN})",
      R"({"v": 0.5, "w": 0} trailing)",
      R"({"v": 0.5, "w": 0}{"v": 1, "w": 0})",
      "{\"v\": 0.5, \"w\": 0, \"x\": \"\xff\xfe\"}",
  };
  for (const auto& body : bodies) {
    const HttpReply reply = operator_client().post("/api/v1/teleop", body);
    EXPECT_EQ(reply.status, 400) << body << " -> " << reply.body;
    const std::string code = reply.error_code();
    EXPECT_TRUE(code == "malformed_json" || code == "invalid_body" || code == "missing_field" ||
                code == "invalid_field")
        << body << " -> " << code;
  }
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  const json state = robot_state(viewer());
  EXPECT_EQ(state.at("mode"), "idle");
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 1e-3);
  EXPECT_LT(pose_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.005)
      << "a refused teleop moved the robot";
}

TEST_F(TeleopEstopTest, ValidationErrorsNameTheField) {
  HttpReply reply = operator_client().post("/api/v1/teleop", R"({"v": 0.5})");
  ASSERT_EQ(reply.status, 400);
  EXPECT_EQ(reply.error_code(), "missing_field");
  EXPECT_NE(reply.json().at("error").at("message").get<std::string>().find('w'), std::string::npos);
  reply = operator_client().post("/api/v1/teleop", R"({"v": 0.5, "w": 0, "ttl_ms": 5000})");
  ASSERT_EQ(reply.status, 400);
  EXPECT_EQ(reply.error_code(), "invalid_field");
  EXPECT_NE(reply.json().at("error").at("message").get<std::string>().find("ttl_ms"),
            std::string::npos);
}

TEST_F(TeleopEstopTest, TtlBoundsAreAccepted) {
  for (const int ttl : {50, 1000}) {
    const HttpReply reply =
        operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}, {"ttl_ms", ttl}});
    EXPECT_EQ(reply.status, 200) << ttl << ": " << reply.body;
  }
}

TEST_F(TeleopEstopTest, EstopEngageAndRelease) {
  const std::int64_t run = current_run_id(viewer());
  HttpReply reply = operator_client().post("/api/v1/estop", json{{"engaged", true}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.json(), (json{{"estop", true}}));
  json state = robot_state(viewer());
  EXPECT_TRUE(state.at("estop").get<bool>());
  EXPECT_EQ(state.at("mode"), "estop");

  // Engaging twice is fine and keeps it engaged.
  reply = operator_client().post("/api/v1/estop", json{{"engaged", true}});
  ASSERT_EQ(reply.status, 200);
  EXPECT_TRUE(reply.json().at("estop").get<bool>());

  const json engaged_event = find_event(viewer(), run, "estop");
  ASSERT_FALSE(engaged_event.is_null());
  EXPECT_EQ(engaged_event.at("detail").at("engaged"), true) << engaged_event.dump();

  reply = operator_client().post("/api/v1/estop", json{{"engaged", false}});
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(reply.json(), (json{{"estop", false}}));
  state = robot_state(viewer());
  EXPECT_FALSE(state.at("estop").get<bool>());
  EXPECT_EQ(state.at("mode"), "idle");
  const json released_event = find_event(viewer(), run, "estop");
  ASSERT_FALSE(released_event.is_null());
  EXPECT_EQ(released_event.at("detail").at("engaged"), false) << released_event.dump();

  // Teleop works again after the release.
  EXPECT_EQ(operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 200);
}

TEST_F(TeleopEstopTest, TeleopUnderEstopIs409AndDoesNotMove) {
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  const json truth = sim_truth(viewer());
  for (int i = 0; i < 20; ++i) {
    const HttpReply reply =
        operator_client().post("/api/v1/teleop", json{{"v", 1.0}, {"w", 0.5}, {"ttl_ms", 1000}});
    ASSERT_EQ(reply.status, 409) << reply.body;
    EXPECT_EQ(reply.error_code(), "estop_engaged");
  }
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  const json state = robot_state(viewer());
  EXPECT_EQ(state.at("mode"), "estop");
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 1e-3);
  EXPECT_LT(pose_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.005);
  // Releasing does not replay the refused commands.
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  EXPECT_NEAR(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.0, 1e-3);
  EXPECT_LT(pose_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.005);
}

TEST_F(TeleopEstopTest, EstopStopsAMovingRobot) {
  drive_for(operator_client(), 1.0, 0.0, 1.5);
  ASSERT_GT(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.5);
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  // E-stop bypasses the acceleration limit: the robot stops within a couple of control periods.
  ASSERT_TRUE(wait_robot_time(viewer(), 0.1));
  const json state = robot_state(viewer());
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 0.05) << state.dump();
  const json truth = sim_truth(viewer());
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  EXPECT_LT(pose_distance(truth.at("pose"), sim_truth(viewer()).at("pose")), 0.01);
}

TEST_F(TeleopEstopTest, InvalidEstopIsRefusedAndChangesNothing) {
  for (const std::string body :
       {R"({})", R"({"engaged":"true"})", R"({"engaged":1})", R"({"engaged":null})",
        R"({"engage":true})", R"([true])", "true", "{engaged:true}", ""}) {
    const HttpReply reply = operator_client().post("/api/v1/estop", body);
    EXPECT_EQ(reply.status, 400) << body << " -> " << reply.body;
  }
  EXPECT_FALSE(robot_state(viewer()).at("estop").get<bool>());
}

TEST_F(TeleopEstopTest, ModeFollowsTheCommands) {
  EXPECT_EQ(robot_state(viewer()).at("mode"), "idle");
  ASSERT_EQ(operator_client()
                .post("/api/v1/teleop", json{{"v", 0.1}, {"w", 0.0}, {"ttl_ms", 1000}})
                .status,
            200);
  EXPECT_EQ(robot_state(viewer()).at("mode"), "teleop");
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  EXPECT_EQ(robot_state(viewer()).at("mode"), "estop");
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  // The e-stop dropped the teleop command: nothing drives the robot after the release.
  EXPECT_EQ(robot_state(viewer()).at("mode"), "idle");
}

TEST_F(TeleopEstopTest, RobotStateHasTheContractFields) {
  const json state = robot_state(viewer());
  for (const char* key :
       {"t", "mode", "pose", "velocity", "localization", "kinematics", "estop", "sensors"}) {
    EXPECT_TRUE(state.contains(key)) << key;
  }
  EXPECT_TRUE(state.at("t").is_number());
  for (const char* key : {"x", "y", "theta"})
    EXPECT_TRUE(state.at("pose").at(key).is_number()) << key;
  EXPECT_TRUE(state.at("velocity").at("v").is_number());
  EXPECT_TRUE(state.at("velocity").at("w").is_number());
  EXPECT_TRUE(state.at("localization").at("method").is_string());
  ASSERT_TRUE(state.at("localization").at("cov").is_array());
  EXPECT_EQ(state.at("localization").at("cov").size(), 9U);
  EXPECT_EQ(state.at("kinematics"), "differential");
  EXPECT_TRUE(state.at("estop").is_boolean());
  ASSERT_TRUE(state.at("sensors").is_object());
  for (const char* sensor : {"encoders", "laser", "sonar", "compass"}) {
    ASSERT_TRUE(state.at("sensors").contains(sensor))
        << sensor << " in " << state.at("sensors").dump();
    EXPECT_TRUE(state.at("sensors").at(sensor).at("ok").is_boolean());
    EXPECT_TRUE(state.at("sensors").at(sensor).at("rate_hz").is_number());
  }
  // At the start pose of the office world.
  EXPECT_NEAR(state.at("pose").at("x").get<double>(), 2.0, 0.05);
  EXPECT_NEAR(state.at("pose").at("y").get<double>(), 7.5, 0.05);
}

}  // namespace
}  // namespace mobot::testing

// The simulator endpoints: worlds, truth, reset, clock, obstacles, and collisions (2D walls and the
// 3D gate beam of g2_lobby).
#include <numbers>
#include <set>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class SimTest : public ServerSuite<SimTest> {
 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  }
  void TearDown() override {
    // Back to the office world at its start, at the suite's time scale.
    operator_client().put("/api/v1/sim/clock", json{{"time_scale", 10}});
    operator_client().post("/api/v1/sim/reset", json{{"world", "office"}});
    ServerSuite::TearDown();
  }

  static std::string active_map_name() {
    for (const auto& map : viewer().get("/api/v1/maps").json()) {
      if (map.at("active").get<bool>()) return map.at("name");
    }
    return "";
  }
};

TEST_F(SimTest, WorldsAreListed) {
  const HttpReply reply = viewer().get("/api/v1/worlds");
  ASSERT_EQ(reply.status, 200);
  const json worlds = reply.json();
  ASSERT_TRUE(worlds.is_array());
  std::set<std::string> names;
  for (const auto& world : worlds) {
    ASSERT_TRUE(world.at("name").is_string());
    ASSERT_TRUE(world.at("description").is_string());
    EXPECT_FALSE(world.at("description").get<std::string>().empty());
    names.insert(world.at("name").get<std::string>());
  }
  EXPECT_TRUE(names.count("office")) << reply.body;
  EXPECT_TRUE(names.count("g2_lobby")) << reply.body;
}

TEST_F(SimTest, TruthHasPoseCollisionsAndAdvancingTime) {
  const json first = sim_truth(viewer());
  for (const char* key : {"t", "pose", "collisions"})
    ASSERT_TRUE(first.contains(key)) << first.dump();
  EXPECT_TRUE(first.at("collisions").is_number_integer());
  for (const char* key : {"x", "y", "theta"}) EXPECT_TRUE(first.at("pose").at(key).is_number());
  ASSERT_TRUE(wait_robot_time(viewer(), 0.2));
  EXPECT_GT(sim_truth(viewer()).at("t").get<double>(), first.at("t").get<double>());
}

TEST_F(SimTest, ResetToAPoseWithASeed) {
  const HttpReply reply = operator_client().post(
      "/api/v1/sim/reset", json{{"pose", {{"x", 5.0}, {"y", 7.2}, {"theta", 1.0}}}, {"seed", 7}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.json(), (json{{"ok", true}}));
  const json truth = sim_truth(viewer());
  EXPECT_NEAR(truth.at("pose").at("x").get<double>(), 5.0, 1e-3);
  EXPECT_NEAR(truth.at("pose").at("y").get<double>(), 7.2, 1e-3);
  EXPECT_NEAR(truth.at("pose").at("theta").get<double>(), 1.0, 1e-3);
  // The estimate restarts at the new pose too.
  const json state = robot_state(viewer());
  EXPECT_NEAR(state.at("pose").at("x").get<double>(), 5.0, 0.01);
  EXPECT_NEAR(state.at("pose").at("y").get<double>(), 7.2, 0.01);
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 1e-3);
  const json event = find_event(viewer(), current_run_id(viewer()), "sim_reset");
  ASSERT_FALSE(event.is_null());
  EXPECT_EQ(event.at("detail").at("seed"), 7) << event.dump();
  EXPECT_EQ(event.at("detail").at("world"), "office") << event.dump();
}

TEST_F(SimTest, ResetWithoutABodyGoesBackToTheStart) {
  ASSERT_EQ(
      operator_client().post("/api/v1/sim/reset", json{{"pose", {{"x", 5.0}, {"y", 7.5}}}}).status,
      200);
  HttpReply reply = operator_client().post("/api/v1/sim/reset", "");
  ASSERT_EQ(reply.status, 200) << reply.body;
  json pose = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(pose.at("x").get<double>(), 2.0, 1e-3);
  EXPECT_NEAR(pose.at("y").get<double>(), 7.5, 1e-3);
  ASSERT_EQ(
      operator_client().post("/api/v1/sim/reset", json{{"pose", {{"x", 5.0}, {"y", 7.5}}}}).status,
      200);
  reply = operator_client().post("/api/v1/sim/reset", "{}");
  ASSERT_EQ(reply.status, 200) << reply.body;
  pose = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(pose.at("x").get<double>(), 2.0, 1e-3);
}

TEST_F(SimTest, ResetToAnotherWorldSwitchesTheActiveMap) {
  HttpReply reply = operator_client().post("/api/v1/sim/reset", json{{"world", "g2_lobby"}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  json pose = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(pose.at("x").get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(pose.at("y").get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(pose.at("theta").get<double>(), std::numbers::pi / 2, 1e-3);
  EXPECT_EQ(active_map_name(), "g2_lobby");
  const json event = find_event(viewer(), current_run_id(viewer()), "sim_reset");
  ASSERT_FALSE(event.is_null());
  EXPECT_EQ(event.at("detail").at("world"), "g2_lobby");

  reply = operator_client().post("/api/v1/sim/reset",
                                 json{{"world", "office"}, {"pose", {{"x", 3.0}, {"y", 7.5}}}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  pose = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(pose.at("x").get<double>(), 3.0, 1e-3);
  EXPECT_EQ(active_map_name(), "office");
}

TEST_F(SimTest, InvalidResetsAre400AndChangeNothing) {
  ASSERT_EQ(
      operator_client().post("/api/v1/sim/reset", json{{"pose", {{"x", 4.0}, {"y", 7.5}}}}).status,
      200);
  const auto events_before =
      viewer()
          .get("/api/v1/runs/" + std::to_string(current_run_id(viewer())) + "/events")
          .json()
          .size();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"world":"atlantis"})", "unknown_world"},
      {R"({"world":"/nonexistent/world.yaml"})", "unknown_world"},
      {R"({"world":"atlantis","pose":{"x":1,"y":1}})", "unknown_world"},
      {R"({"pose":{"x":0.1,"y":0.1}})", "pose_in_obstacle"},    // inside the outer wall
      {R"({"pose":{"x":5.0,"y":6.45}})", "pose_in_obstacle"},   // on the corridor wall
      {R"({"pose":{"x":50.0,"y":50.0}})", "pose_in_obstacle"},  // outside the world
      {R"({"world":"g2_lobby","pose":{"x":0,"y":3.15}})", "pose_in_obstacle"},  // in gate A's beam
      {R"({"world":""})", "invalid_field"},
      {R"({"world":5})", "invalid_field"},
      {R"({"pose":"here"})", "invalid_field"},
      {R"({"pose":{"x":1}})", "missing_field"},
      {R"({"pose":{"x":"1","y":1}})", "invalid_field"},
      {R"({"pose":{"x":1e7,"y":1}})", "invalid_field"},
      {R"({"pose":{"x":NaN,"y":1}})", "malformed_json"},
      {R"({"seed":-1})", "invalid_field"},
      {R"({"seed":"7"})", "invalid_field"},
      {R"({"seed":1e20})", "invalid_field"},
      {"[1]", "invalid_body"},
      {"{", "malformed_json"},
  };
  for (const auto& [body, code] : cases) {
    const HttpReply reply = operator_client().post("/api/v1/sim/reset", body);
    EXPECT_EQ(reply.status, 400) << body << " -> " << reply.body;
    if (!code.empty()) {
      EXPECT_EQ(reply.error_code(), code) << body;
    }
  }
  const json pose = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(pose.at("x").get<double>(), 4.0, 1e-3);
  EXPECT_NEAR(pose.at("y").get<double>(), 7.5, 1e-3);
  EXPECT_EQ(active_map_name(), "office");
  const auto events_after =
      viewer()
          .get("/api/v1/runs/" + std::to_string(current_run_id(viewer())) + "/events")
          .json()
          .size();
  EXPECT_EQ(events_after, events_before) << "a refused reset recorded an event";
}

// The robot clock is the time base of the run (trajectory, events) and of the safety watchdog:
// restarting the simulation must not turn it back.
TEST_F(SimTest, ResetDoesNotTurnTheRobotClockBack) {
  ASSERT_TRUE(wait_until([&] { return robot_time(viewer()) > 1.0; }, 30s));
  const double before = robot_time(viewer());
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  EXPECT_GE(robot_time(viewer()), before) << "the robot clock went back on a reset";
  EXPECT_GE(sim_truth(viewer()).at("t").get<double>(), before);
  ASSERT_TRUE(wait_robot_time(viewer(), 0.3));
  const json samples =
      viewer()
          .get("/api/v1/runs/" + std::to_string(current_run_id(viewer())) + "/trajectory")
          .json();
  int backwards = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if (samples[i].at("t").get<double>() <= samples[i - 1].at("t").get<double>()) ++backwards;
  }
  EXPECT_EQ(backwards, 0) << "the run's trajectory goes back in time";
}

TEST_F(SimTest, SensorHealthIsRightAfterAReset) {
  ASSERT_TRUE(wait_until([&] { return robot_time(viewer()) > 1.5; }, 30s));
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  ASSERT_TRUE(wait_robot_time(viewer(), 1.5));
  const json sensors = robot_state(viewer()).at("sensors");
  EXPECT_NEAR(sensors.at("laser").at("rate_hz").get<double>(), 10.0, 1.5) << sensors.dump();
  EXPECT_NEAR(sensors.at("encoders").at("rate_hz").get<double>(), 50.0, 7.5) << sensors.dump();
}

TEST_F(SimTest, ClockChangesTheRateOfRobotTime) {
  HttpReply reply = operator_client().put("/api/v1/sim/clock", json{{"time_scale", 50}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_DOUBLE_EQ(reply.json().at("time_scale").get<double>(), 50.0);
  double t0 = robot_time(viewer());
  std::this_thread::sleep_for(1s);
  const double fast = robot_time(viewer()) - t0;
  EXPECT_GT(fast, 15.0) << "at x50, one wall second is 50 robot seconds";

  reply = operator_client().put("/api/v1/sim/clock", json{{"time_scale", 0.5}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  t0 = robot_time(viewer());
  std::this_thread::sleep_for(1s);
  const double slow = robot_time(viewer()) - t0;
  EXPECT_LT(slow, 1.0) << "at x0.5, one wall second is half a robot second";
  EXPECT_GT(slow, 0.1);

  for (const double scale : {0.1, 100.0}) {
    EXPECT_EQ(operator_client().put("/api/v1/sim/clock", json{{"time_scale", scale}}).status, 200)
        << scale;
  }
}

TEST_F(SimTest, InvalidClockIsRefusedAndChangesNothing) {
  ASSERT_EQ(operator_client().put("/api/v1/sim/clock", json{{"time_scale", 0.5}}).status, 200);
  for (const std::string body :
       {R"({"time_scale":0.05})", R"({"time_scale":0})", R"({"time_scale":-1})",
        R"({"time_scale":100.5})", R"({"time_scale":1000})", R"({"time_scale":"fast"})",
        R"({"time_scale":null})", R"({})", R"({"time_scale":NaN})", R"({"time_scale":[10]})", "",
        "10"}) {
    const HttpReply reply = operator_client().request("PUT", "/api/v1/sim/clock", body);
    EXPECT_EQ(reply.status, 400) << body << " -> " << reply.body;
  }
  // Still at x0.5.
  const double t0 = robot_time(viewer());
  std::this_thread::sleep_for(1s);
  EXPECT_LT(robot_time(viewer()) - t0, 1.0) << "a refused clock change took effect";
}

TEST_F(SimTest, ObstaclesAddAndDelete) {
  HttpReply reply = operator_client().post("/api/v1/sim/obstacles",
                                           json{{"x", 6.0}, {"y", 7.5}, {"radius", 0.3}});
  ASSERT_EQ(reply.status, 201) << reply.body;
  ASSERT_TRUE(reply.json().at("id").is_number_integer());
  const int first = reply.json().at("id").get<int>();
  reply = operator_client().post("/api/v1/sim/obstacles",
                                 json{{"x", 8.0}, {"y", 7.5}, {"radius", 0.2}, {"height", 0.5}});
  ASSERT_EQ(reply.status, 201) << reply.body;
  const int second = reply.json().at("id").get<int>();
  EXPECT_NE(first, second);

  reply = operator_client().del("/api/v1/sim/obstacles/" + std::to_string(first));
  EXPECT_EQ(reply.status, 204) << reply.body;
  EXPECT_TRUE(reply.body.empty());
  reply = operator_client().del("/api/v1/sim/obstacles/" + std::to_string(first));
  EXPECT_EQ(reply.status, 404);
  EXPECT_EQ(reply.error_code(), "unknown_obstacle");
  EXPECT_EQ(operator_client().del("/api/v1/sim/obstacles/" + std::to_string(second)).status, 204);
  for (const std::string id : {"999999", "0", "-1", "abc", "99999999999"}) {
    reply = operator_client().del("/api/v1/sim/obstacles/" + id);
    EXPECT_EQ(reply.status, 404) << id;
    EXPECT_EQ(reply.error_code(), "unknown_obstacle") << id;
  }
}

TEST_F(SimTest, AnObstacleBlocksTheLaser) {
  // The robot at (2, 7.5) faces east down the corridor; the laser sees the far wall ~17 m away.
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  WsClient stream(port(), viewer_token());
  stream.send({{"op", "subscribe"}, {"topics", {"scan"}}, {"encoding", "json"}});
  auto ahead = [&stream]() {
    const auto scan = stream.read_until("scan", 5s);
    EXPECT_TRUE(scan.has_value());
    if (!scan) return -1.0;
    const json& ranges = scan->at("data").at("ranges");
    return ranges.at(ranges.size() / 2).get<double>();
  };
  EXPECT_GT(ahead(), 10.0);
  const HttpReply reply = operator_client().post("/api/v1/sim/obstacles",
                                                 json{{"x", 5.0}, {"y", 7.5}, {"radius", 0.3}});
  ASSERT_EQ(reply.status, 201);
  // The laser (at x 2.2) sees the cylinder's near side at x 4.7, 2.5 m ahead.
  double range = -1.0;
  ASSERT_TRUE(wait_until(
      [&] {
        range = ahead();
        return std::abs(range - 2.5) < 0.1;
      },
      5s))
      << range;
  ASSERT_EQ(operator_client()
                .del("/api/v1/sim/obstacles/" + std::to_string(reply.json().at("id").get<int>()))
                .status,
            204);
  EXPECT_TRUE(wait_until([&] { return ahead() > 10.0; }, 5s));
}

TEST_F(SimTest, ResetIntoAnAddedObstacleIsRefused) {
  const HttpReply reply = operator_client().post("/api/v1/sim/obstacles",
                                                 json{{"x", 6.0}, {"y", 7.5}, {"radius", 0.4}});
  ASSERT_EQ(reply.status, 201);
  const HttpReply reset =
      operator_client().post("/api/v1/sim/reset", json{{"pose", {{"x", 6.0}, {"y", 7.5}}}});
  EXPECT_EQ(reset.status, 400) << reset.body;
  EXPECT_EQ(reset.error_code(), "pose_in_obstacle");
  operator_client().del("/api/v1/sim/obstacles/" +
                        std::to_string(reply.json().at("id").get<int>()));
}

TEST_F(SimTest, InvalidObstaclesAre400) {
  for (const std::string body :
       {R"({"y":1,"radius":0.3})", R"({"x":1,"radius":0.3})", R"({"x":1,"y":1})",
        R"({"x":1,"y":1,"radius":0})", R"({"x":1,"y":1,"radius":0.001})",
        R"({"x":1,"y":1,"radius":11})", R"({"x":1,"y":1,"radius":-0.3})",
        R"({"x":1,"y":1,"radius":0.3,"height":0})", R"({"x":1,"y":1,"radius":0.3,"height":101})",
        R"({"x":1e5,"y":1,"radius":0.3})", R"({"x":"1","y":1,"radius":0.3})",
        R"({"x":NaN,"y":1,"radius":0.3})", "[]", ""}) {
    const HttpReply reply = operator_client().post("/api/v1/sim/obstacles", body);
    EXPECT_EQ(reply.status, 400) << body << " -> " << reply.body;
  }
}

TEST_F(SimTest, DrivingIntoAWallIsACollision) {
  // Facing north in the corridor: the wall at y 8.5 is 0.7 m ahead of the front edge.
  ASSERT_EQ(operator_client()
                .post("/api/v1/sim/reset",
                      json{{"pose", {{"x", 2.0}, {"y", 7.5}, {"theta", std::numbers::pi / 2}}}})
                .status,
            200);
  const int collisions0 = sim_truth(viewer()).at("collisions").get<int>();
  const std::int64_t run = current_run_id(viewer());
  drive_for(operator_client(), 0.5, 0.0, 6.0,
            [&] { return sim_truth(viewer()).at("collisions").get<int>() > collisions0; });
  const json truth = sim_truth(viewer());
  ASSERT_GT(truth.at("collisions").get<int>(), collisions0)
      << "no collision after 6 s towards a wall";
  // The body did not pass through the wall (front edge at y + 0.3).
  EXPECT_LT(truth.at("pose").at("y").get<double>(), 8.5 - 0.3 + 0.05) << truth.dump();
  EXPECT_GT(truth.at("pose").at("y").get<double>(), 7.6) << truth.dump();

  // The collision stopped the robot: no motion while nobody commands it (a command sent just
  // before the collision was seen has a 0.3 s ttl).
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));
  const json state = robot_state(viewer());
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 0.02) << state.dump();
  const json still = sim_truth(viewer());
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  EXPECT_NEAR(sim_truth(viewer()).at("pose").at("y").get<double>(),
              still.at("pose").at("y").get<double>(), 0.005);

  const json event = find_event(viewer(), run, "collision");
  ASSERT_FALSE(event.is_null()) << "no collision event recorded";
  EXPECT_TRUE(event.at("detail").is_object()) << event.dump();

  const HttpReply metrics = viewer().get("/metrics");
  EXPECT_EQ(metrics.body.find("mobot_collisions_total 0\n"), std::string::npos);
}

TEST_F(SimTest, GateABeamIsA3DCollisionButGateBIsPassable) {
  // g2_lobby: gate A (straight ahead of the start) is open on the floor plan, but its beam
  // (0.8..1.0 m) is below the 1.2 m body.
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json{{"world", "g2_lobby"}}).status, 200);
  int collisions0 = sim_truth(viewer()).at("collisions").get<int>();
  drive_for(operator_client(), 0.8, 0.0, 8.0,
            [&] { return sim_truth(viewer()).at("collisions").get<int>() > collisions0; });
  json truth = sim_truth(viewer());
  EXPECT_GT(truth.at("collisions").get<int>(), collisions0)
      << "drove through gate A's beam: " << truth.dump();
  EXPECT_LT(truth.at("pose").at("y").get<double>(), 3.0) << truth.dump();

  // Gate B (x -2.9..-1.5) has its beam at 1.7 m: the robot passes under it.
  ASSERT_EQ(operator_client()
                .post("/api/v1/sim/reset",
                      json{{"world", "g2_lobby"},
                           {"pose", {{"x", -2.2}, {"y", 0.0}, {"theta", std::numbers::pi / 2}}}})
                .status,
            200);
  collisions0 = sim_truth(viewer()).at("collisions").get<int>();
  drive_for(operator_client(), 0.8, 0.0, 6.5,
            [&] { return sim_truth(viewer()).at("pose").at("y").get<double>() > 4.0; });
  truth = sim_truth(viewer());
  EXPECT_EQ(truth.at("collisions").get<int>(), collisions0) << truth.dump();
  EXPECT_GT(truth.at("pose").at("y").get<double>(), 3.6)
      << "did not get through gate B: " << truth.dump();
}

}  // namespace
}  // namespace mobot::testing

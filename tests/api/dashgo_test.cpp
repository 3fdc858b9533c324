// The Dashgo D1 workflow of docs/algorithms.md C7 end to end on the simulated office, in one server
// (the steps build on each other): map the building by a scripted teleop tour and save the map;
// the SLAM pose stays with the truth and the map's walls with the world's; then localize globally
// on the saved map, drive goals with DWA, recover from a kidnap, avoid the table top only the IR
// ring sees, route around a keep-out zone. The robot starts without a map (sim.provide_map false).
//
// The steps share one server and run in order: CTest runs the suite as one test
// (tests/api/CMakeLists.txt), never a step alone.
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>

#include "support/api_test.h"
#include "support/goal_support.h"

namespace mobot::testing {
namespace {

struct Point {
  double x;
  double y;
};

// The office world's floor plan as the simulator has it (its PGM next to world.yaml).
GridMap office_floor_plan() {
  GridMap map;
  std::ifstream in(std::string(MOBOT_SOURCE_ROOT) + "/drivers/sim/worlds/office/office.pgm",
                   std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_TRUE(parse_pgm(bytes.str(), map.width, map.height, map.pixels));
  map.resolution = 0.05;
  return map;
}

class DashgoTest : public ServerSuite<DashgoTest> {
 public:
  static MobotdProcess::Options server_options() {
    MobotdProcess::Options options;
    options.extra_args = {"--config",
                          std::string(MOBOT_SOURCE_ROOT) + "/deploy/config/dashgo_d1.yaml",
                          "--world", "office"};
    options.time_scale = 5.0;
    return options;
  }

 protected:
  static json truth_pose() { return sim_truth(viewer()).at("pose"); }
  static json estimate() { return robot_state(viewer()).at("pose"); }
  static double position_error() {
    const json truth = truth_pose();
    const json pose = estimate();
    return std::hypot(pose.at("x").get<double>() - truth.at("x").get<double>(),
                      pose.at("y").get<double>() - truth.at("y").get<double>());
  }

  // Teleop towards `target` from the true pose, as an operator watching the robot would: turn,
  // then drive, within the Dashgo's limits. Calls `sample` between commands. False on time-out.
  static bool drive_to(const Point& target, const std::function<void()>& sample) {
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    while (std::chrono::steady_clock::now() < deadline) {
      const json pose = truth_pose();
      const double dx = target.x - pose.at("x").get<double>();
      const double dy = target.y - pose.at("y").get<double>();
      const double distance = std::hypot(dx, dy);
      if (distance < 0.15) return true;
      const double heading = std::atan2(dy, dx) - pose.at("theta").get<double>();
      const double error = std::atan2(std::sin(heading), std::cos(heading));
      const double w = std::clamp(1.5 * error, -0.5, 0.5);
      const double v = std::abs(error) > 0.4 ? 0.0 : std::min(0.3, 0.6 * distance);
      const HttpReply reply =
          operator_client().post("/api/v1/teleop", json{{"v", v}, {"w", w}, {"ttl_ms", 300}});
      if (reply.status != 200) return false;
      if (sample) sample();
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  // Teleop on the spot until the true heading is `heading_rad` (within 0.05 rad). False on
  // time-out.
  static bool turn_to(double heading_rad) {
    const auto deadline = std::chrono::steady_clock::now() + 30s;
    while (std::chrono::steady_clock::now() < deadline) {
      const double error = heading_rad - truth_pose().at("theta").get<double>();
      const double wrapped = std::atan2(std::sin(error), std::cos(error));
      if (std::abs(wrapped) < 0.05) return true;
      const double w = std::clamp(1.5 * wrapped, -0.5, 0.5);
      if (operator_client()
              .post("/api/v1/teleop", json{{"v", 0.0}, {"w", w}, {"ttl_ms", 300}})
              .status != 200) {
        return false;
      }
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  static void stop_robot() {
    operator_client().post("/api/v1/teleop", json{{"v", 0}, {"w", 0}, {"ttl_ms", 300}});
  }

  static inline std::int64_t saved_map_id_ = -1;
};

TEST_F(DashgoTest, A_StartsWithoutAMapAndGlobalLocalizationNeedsOne) {
  EXPECT_EQ(active_map_id(viewer()), -1);
  const HttpReply global = operator_client().post("/api/v1/localization/global", "");
  EXPECT_EQ(global.status, 409);
  EXPECT_EQ(global.error_code(), "no_map");
  const json state = robot_state(viewer());
  EXPECT_EQ(state.at("kinematics"), "differential");
  EXPECT_TRUE(state.at("sensors").contains("ir")) << state.dump();
}

TEST_F(DashgoTest, B_MapsTheOfficeWithTheSlamPoseOnTheTruth) {
  ASSERT_EQ(operator_client().post("/api/v1/mapping", json{{"action", "start"}}).status, 200);
  // Along the corridor east, back, down the north-south corridor and back to the start: a loop.
  const std::vector<Point> tour = {{6.0, 7.5},  {12.0, 7.5}, {17.5, 7.5}, {10.0, 7.6},
                                   {10.0, 4.0}, {10.0, 1.5}, {10.0, 7.4}, {2.5, 7.5}};
  double worst_m = 0.0;
  int samples = 0;
  auto sample = [&] {
    if (++samples % 10 != 0) return;
    worst_m = std::max(worst_m, position_error());
  };
  for (const Point& waypoint : tour) {
    ASSERT_TRUE(drive_to(waypoint, sample)) << "did not reach " << waypoint.x << ", " << waypoint.y;
  }
  stop_robot();
  std::cout << "[ info ] SLAM pose at most " << worst_m << " m off the truth\n";
  EXPECT_LT(worst_m, 0.10) << "the SLAM pose left the truth by " << worst_m << " m";
  const json status = viewer().get("/api/v1/mapping").json();
  EXPECT_GT(status.at("nodes").get<int>(), 50) << status.dump();
  const HttpReply stop =
      operator_client().post("/api/v1/mapping", json{{"action", "stop"}, {"save_as", "office"}});
  ASSERT_EQ(stop.status, 200) << stop.body;
  saved_map_id_ = stop.json().at("map_id").get<std::int64_t>();
  EXPECT_EQ(active_map_id(viewer()), saved_map_id_);

  // Every occupied cell of the saved map lies within 0.10 m of a wall of the world (95 %).
  const GridMap saved = fetch_active_map(viewer());
  const GridMap world = office_floor_plan();
  ASSERT_TRUE(saved.valid() && world.valid());
  int occupied = 0;
  int near_wall = 0;
  for (int row = 0; row < saved.height; ++row) {
    for (int col = 0; col < saved.width; ++col) {
      if (saved.pixels[static_cast<std::size_t>(saved.height - 1 - row) * saved.width + col] != 0)
        continue;
      ++occupied;
      const double x = saved.origin_x + (col + 0.5) * saved.resolution;
      const double y = saved.origin_y + (row + 0.5) * saved.resolution;
      near_wall += world.clearance(x, y, 0.2) <= 0.10 ? 1 : 0;
    }
  }
  ASSERT_GT(occupied, 500);
  EXPECT_GE(near_wall, 0.95 * occupied) << near_wall << " of " << occupied << " occupied cells";
}

TEST_F(DashgoTest, C_LocalizesGloballyOnTheSavedMap) {
  ASSERT_GT(saved_map_id_, 0) << "needs the map of the previous test";
  const HttpReply global = operator_client().post("/api/v1/localization/global", "");
  ASSERT_EQ(global.status, 202) << global.body;
  EXPECT_EQ(robot_state(viewer()).at("localization").at("converged"), false);
  // Turn on the spot and drive along the corridor until the cloud settles.
  const std::vector<Point> route = {{6.0, 7.5}, {2.5, 7.5}, {6.0, 7.5}};
  for (const Point& waypoint : route) {
    drive_to(waypoint, nullptr);
    if (robot_state(viewer()).at("localization").at("converged").get<bool>()) break;
  }
  stop_robot();
  ASSERT_TRUE(wait_until(
      [] { return robot_state(viewer()).at("localization").at("converged").get<bool>(); }, 20s));
  EXPECT_LT(position_error(), 0.15);
}

TEST_F(DashgoTest, D_TenGoalsWithDwaAndNoCollision) {
  ASSERT_GT(saved_map_id_, 0);
  const int collisions_before = sim_truth(viewer()).at("collisions").get<int>();
  const std::vector<Point> goals = {{6.0, 7.5},  {12.0, 7.5}, {10.0, 4.0}, {10.0, 1.5}, {10.0, 7.5},
                                    {16.5, 7.5}, {12.0, 7.2}, {8.0, 7.8},  {4.0, 7.5},  {2.5, 7.5}};
  int succeeded = 0;
  for (const Point& goal : goals) {
    const HttpReply reply = operator_client().post(
        "/api/v1/goals", json{{"x", goal.x}, {"y", goal.y}, {"controller", "dwa"}});
    ASSERT_EQ(reply.status, 201) << reply.body;
    const json end = wait_goal_end(viewer(), reply.json().at("id").get<std::int64_t>(), 120.0);
    succeeded += end.value("status", "") == "succeeded" ? 1 : 0;
    EXPECT_EQ(end.value("status", ""), "succeeded") << end.dump();
  }
  EXPECT_EQ(succeeded, 10);
  EXPECT_EQ(sim_truth(viewer()).at("collisions").get<int>(), collisions_before);
}

// The corridor is the filter's hardest place: it looks alike along its length, and only the beams
// that return nothing (its open length against a wall the map puts across them) tell a pose
// from the one turned round at its other end.
TEST_F(DashgoTest, E_RecoversFromAKidnapWithin30sOfDriving) {
  ASSERT_GT(saved_map_id_, 0);
  ASSERT_EQ(operator_client()
                .put("/api/v1/localization/method", json{{"method", "particle_filter"}})
                .status,
            200);
  const HttpReply kidnap = operator_client().post(
      "/api/v1/sim/kidnap", json{{"x", 14.0}, {"y", 7.5}, {"theta", std::numbers::pi}});
  ASSERT_EQ(kidnap.status, 200) << kidnap.body;
  ASSERT_GT(position_error(), 1.0);
  const double start = robot_time(viewer());
  bool recovered = false;
  double recovered_after_s = 0.0;
  const std::vector<Point> route = {{10.5, 7.5}, {14.0, 7.5}, {10.5, 7.5}, {14.0, 7.5}};
  for (const Point& waypoint : route) {
    drive_to(waypoint, [&] {
      // The heading too: the pose turned round at the corridor's other end drives the other way
      // and passes the truth once.
      if (recovered || position_error() >= 0.3 || heading_error(estimate(), truth_pose()) >= 0.2)
        return;
      recovered = true;
      recovered_after_s = robot_time(viewer()) - start;
    });
    if (recovered || robot_time(viewer()) - start > 30.0) break;
  }
  stop_robot();
  if (recovered) std::cout << "[ info ] recovered after " << recovered_after_s << " s\n";
  // A leg is about 12 s of driving: the last one may run past the 30 s.
  EXPECT_LE(recovered_after_s, 30.0);
  EXPECT_TRUE(recovered) << "still " << position_error() << " m off after "
                         << robot_time(viewer()) - start << " s";
  EXPECT_LT(position_error(), 0.3) << "found, then lost again";
}

TEST_F(DashgoTest, F_TheIrOnlyTableIsAvoided) {
  ASSERT_GT(saved_map_id_, 0);
  const int collisions_before = sim_truth(viewer()).at("collisions").get<int>();
  // Into the south-west room through its corridor door, then straight at table_ir (x 0.6-1.8,
  // y 3.4-4.2): the lidar passes under its top, the saved map does not have it.
  drive_to({2.6, 7.5}, nullptr);
  drive_to({2.6, 5.6}, nullptr);
  drive_to({1.2, 5.0}, nullptr);
  // Facing the table (south), as the operator would drive at it.
  ASSERT_TRUE(turn_to(-std::numbers::pi / 2.0));
  // Straight at it until the ring reacts (the operator then lets go) or the robot is past it.
  // (The ring may have reacted before, at the door: only a newer event counts.)
  const std::int64_t run_id = current_run_id(viewer());
  const json before = find_event(viewer(), run_id, "ir_safety");
  const double before_t = before.is_null() ? -1.0 : before.at("t").get<double>();
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  json event;
  while (std::chrono::steady_clock::now() < deadline) {
    operator_client().post("/api/v1/teleop", json{{"v", 0.2}, {"w", 0.0}, {"ttl_ms", 300}});
    if (truth_pose().at("y").get<double>() < 4.0) break;
    const json latest = find_event(viewer(), run_id, "ir_safety");
    if (!latest.is_null() && latest.at("t").get<double>() > before_t) {
      event = latest;
      break;
    }
    std::this_thread::sleep_for(10ms);
  }
  stop_robot();
  // The reaction (stop and back off, or turn away) runs its course.
  std::this_thread::sleep_for(2s);
  ASSERT_FALSE(event.is_null()) << "no ir_safety event";
  EXPECT_GT(truth_pose().at("y").get<double>(), 4.2 + 0.2) << "the robot is over the table";
  EXPECT_TRUE(event.at("detail").contains("sensor")) << event.dump();
  EXPECT_EQ(sim_truth(viewer()).at("collisions").get<int>(), collisions_before);
}

TEST_F(DashgoTest, G_AGoalBeyondAKeepoutZoneRoutesAroundIt) {
  ASSERT_GT(saved_map_id_, 0);
  // Out of the south-west room the way F came in (a straight line to the corridor meets a wall,
  // and pushed into it until drive_to's time-out this step took two minutes).
  for (const Point& waypoint :
       {Point{1.2, 5.0}, Point{2.6, 5.6}, Point{2.6, 7.5}, Point{4.0, 7.5}}) {
    ASSERT_TRUE(drive_to(waypoint, nullptr))
        << "did not reach " << waypoint.x << ", " << waypoint.y;
  }
  stop_robot();
  const std::string zones = "/api/v1/maps/" + std::to_string(saved_map_id_) + "/zones";
  // The corridor's northern half between x 6 and 7: the way east is through its southern half.
  const json zone = {{6.0, 7.5}, {7.0, 7.5}, {7.0, 8.5}, {6.0, 8.5}};
  const HttpReply added = operator_client().post(zones, json{{"polygon", zone}});
  ASSERT_EQ(added.status, 201) << added.body;
  const HttpReply goal =
      operator_client().post("/api/v1/goals", json{{"x", 9.0}, {"y", 7.9}, {"controller", "dwa"}});
  ASSERT_EQ(goal.status, 201) << goal.body;
  for (const auto& point : goal.json().at("path")) {
    const double x = point[0].get<double>();
    const double y = point[1].get<double>();
    EXPECT_FALSE(x > 6.0 && x < 7.0 && y > 7.5) << "planned through the zone at " << x << ", " << y;
  }
  bool entered = false;
  const std::int64_t id = goal.json().at("id").get<std::int64_t>();
  ASSERT_TRUE(wait_until(
      [&] {
        const json truth = truth_pose();
        const double x = truth.at("x").get<double>();
        entered = entered || (x > 6.0 && x < 7.0 && truth.at("y").get<double>() > 7.55);
        return goal_finished(viewer().get("/api/v1/goals/" + std::to_string(id)).json());
      },
      60s, 20ms));
  EXPECT_FALSE(entered) << "the robot drove into the keep-out zone";
  EXPECT_EQ(operator_client().post("/api/v1/goals", json{{"x", 6.5}, {"y", 8.0}}).error_code(),
            "goal_in_keepout");
}

}  // namespace
}  // namespace mobot::testing

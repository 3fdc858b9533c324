// 20 random reachable goals in the office world at time scale 20 (fixed seed): every goal
// succeeds, ends within 0.10 m and 0.1 rad of its target by the simulator's truth, and the whole
// tour has no collision; the run counts 20 succeeded goals.
#include <iomanip>
#include <random>

#include "support/goal_support.h"

namespace mobot::testing {
namespace {

constexpr int kGoals = 20;
constexpr std::uint64_t kSeed = 20240520;
constexpr double kClearance_m = 0.6;            // from every non-free map cell
constexpr double kMinTravel_m = 1.0;            // from where the robot stands
constexpr double kRandomGoalTimeout_s = 120.0;  // robot time per goal
constexpr double kPositionTolerance_m = 0.10;
constexpr double kHeadingTolerance_rad = 0.10;

// The office world's 3D boxes (drivers/sim/worlds/office/world.yaml): not on the 2D floor map,
// but the 1.2 m tall robot does not fit under a table top or into the cabinet, so no goal is put
// within the clearance of one.
struct Box {
  const char* name;
  double min_x, min_y, max_x, max_y;
};
constexpr Box kOfficeBoxes[] = {
    {"table_1", 15.0, 11.0, 16.6, 11.8},
    {"table_2", 3.0, 2.5, 4.6, 3.3},
    {"cabinet_1", 0.4, 14.2, 1.6, 14.7},
};

double box_distance(const Box& box, double x, double y) {
  const double dx = std::max({box.min_x - x, 0.0, x - box.max_x});
  const double dy = std::max({box.min_y - y, 0.0, y - box.max_y});
  return std::hypot(dx, dy);
}

class RandomGoalsTest : public ServerSuite<RandomGoalsTest> {
 public:
  static MobotdProcess::Options server_options() {
    MobotdProcess::Options options;
    options.time_scale = 20.0;
    options.extra_args = {"--world", "office"};
    return options;
  }
};

struct Outcome {
  int index = 0;
  json target;
  int post_status = 0;
  std::string post_body;
  json goal;      // as it ended (or as last read)
  json truth;     // GET /sim/truth right after
  json estimate;  // GET /robot right after
  double robot_s = 0.0;
  double wall_s = 0.0;
  double position_error = 0.0;
  double heading_err = 0.0;
  bool ok() const {
    return goal.value("status", "") == "succeeded" && position_error < kPositionTolerance_m &&
           heading_err < kHeadingTolerance_rad;
  }
};

TEST_F(RandomGoalsTest, TwentyRandomReachableGoalsSucceedWithoutCollisions) {
  const auto wall_start = std::chrono::steady_clock::now();
  ASSERT_EQ(sim_truth(viewer()).at("collisions"), 0);
  const GridMap map = fetch_active_map(viewer());
  ASSERT_TRUE(map.valid());
  ASSERT_NEAR(map.max_x() - map.min_x(), 20.0, 1e-6);
  ASSERT_NEAR(map.max_y() - map.min_y(), 15.0, 1e-6);

  std::mt19937_64 rng(kSeed);
  auto uniform = [&](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
  };
  auto draw_target = [&](const json& from) {
    for (int attempt = 0; attempt < 100000; ++attempt) {
      const double x = uniform(map.min_x(), map.max_x());
      const double y = uniform(map.min_y(), map.max_y());
      const double theta = uniform(-std::numbers::pi, std::numbers::pi);
      if (map.clearance(x, y, kClearance_m) < kClearance_m) continue;
      bool near_box = false;
      for (const auto& box : kOfficeBoxes)
        near_box = near_box || box_distance(box, x, y) < kClearance_m;
      if (near_box) continue;
      const json target{{"x", x}, {"y", y}, {"theta", theta}};
      if (xy_distance(target, from) <= kMinTravel_m) continue;
      return target;
    }
    ADD_FAILURE() << "no free point found";
    return json{{"x", 2.0}, {"y", 7.5}, {"theta", 0.0}};
  };

  std::vector<Outcome> outcomes;
  json from = sim_truth(viewer()).at("pose");
  // Collisions counted before each recovery reset (a reset restarts the simulator's count).
  int collisions_before_resets = 0;
  int recoveries = 0;
  for (int i = 0; i < kGoals; ++i) {
    Outcome outcome;
    outcome.index = i + 1;
    // The next target is drawn from where the previous one was (the robot stands there when all
    // goes well), so the sequence of targets does not depend on how well the robot drives.
    outcome.target = draw_target(from);
    from = outcome.target;
    const double t0 = robot_time(viewer());
    const auto w0 = std::chrono::steady_clock::now();
    const HttpReply reply = operator_client().post("/api/v1/goals", outcome.target);
    outcome.post_status = reply.status;
    outcome.post_body = reply.body.substr(0, 300);
    if (reply.status == 201) {
      outcome.goal = wait_goal_end(viewer(), reply.json().at("id"), kRandomGoalTimeout_s);
    }
    outcome.robot_s = robot_time(viewer()) - t0;
    outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    outcome.truth = sim_truth(viewer());
    outcome.estimate = robot_state(viewer());
    outcome.position_error = xy_distance(outcome.truth.at("pose"), outcome.target);
    outcome.heading_err = heading_error(outcome.truth.at("pose"), outcome.target);
    std::cout << std::fixed << std::setprecision(3) << "[ goal " << std::setw(2) << outcome.index
              << " ] target " << pose_text(outcome.target) << " -> "
              << outcome.goal.value("status", "post " + std::to_string(reply.status))
              << (outcome.goal.contains("reason")
                      ? " (" + outcome.goal.at("reason").get<std::string>() + ")"
                      : std::string())
              << "  truth " << pose_text(outcome.truth.at("pose")) << "  err "
              << outcome.position_error << " m " << outcome.heading_err << " rad  ekf-truth "
              << xy_distance(outcome.estimate.at("pose"), outcome.truth.at("pose")) << " m  "
              << std::setprecision(1) << outcome.robot_s << " s robot, " << std::setprecision(2)
              << outcome.wall_s << " s wall, replans " << outcome.goal.value("replans", 0)
              << ", collisions " << outcome.truth.at("collisions") << std::endl;
    if (!outcome.ok()) {
      // Recovery, so that one failure does not decide the fate of the goals after it (a robot
      // jammed against a door jamb stays there): end the goal if it still runs and put the robot
      // where it should have arrived. The failure itself stays a failure below.
      if (outcome.goal.contains("id") && !goal_finished(outcome.goal)) {
        operator_client().del("/api/v1/goals/" + std::to_string(outcome.goal.at("id").get<int>()));
      }
      collisions_before_resets += outcome.truth.at("collisions").get<int>();
      const HttpReply reset =
          operator_client().post("/api/v1/sim/reset", json{{"pose", outcome.target}});
      EXPECT_EQ(reset.status, 200) << reset.body;
      ++recoveries;
      std::cout << "[ recovery ] robot placed at goal " << outcome.index
                << "'s target by a sim reset" << std::endl;
    }
    outcomes.push_back(std::move(outcome));
  }
  const double wall_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::cout << "[ info ] " << kGoals << " goals in " << std::setprecision(1) << wall_total
            << " s wall" << std::endl;

  // Every goal: succeeded, and where it was sent by the simulator's truth.
  const std::int64_t run = current_run_id(viewer());
  int good = 0;
  for (const auto& outcome : outcomes) {
    good += outcome.ok() ? 1 : 0;
    EXPECT_EQ(outcome.post_status, 201) << "goal " << outcome.index << " "
                                        << pose_text(outcome.target) << ": " << outcome.post_body;
    EXPECT_EQ(outcome.goal.value("status", ""), "succeeded")
        << "goal " << outcome.index << " " << pose_text(outcome.target) << ": "
        << outcome.goal.dump().substr(0, 200) << "; truth " << pose_text(outcome.truth.at("pose"));
    EXPECT_LT(outcome.position_error, kPositionTolerance_m)
        << "goal " << outcome.index << " " << pose_text(outcome.target) << " truth "
        << pose_text(outcome.truth.at("pose"));
    EXPECT_LT(outcome.heading_err, kHeadingTolerance_rad)
        << "goal " << outcome.index << " " << pose_text(outcome.target) << " truth "
        << pose_text(outcome.truth.at("pose"));
    if (!outcome.ok() && outcome.goal.contains("id")) {
      for (const auto& event : goal_events(viewer(), run, outcome.goal.at("id"))) {
        std::cout << "  goal " << outcome.index << " event " << event.dump() << std::endl;
      }
    }
  }
  EXPECT_EQ(good, kGoals);
  EXPECT_EQ(recoveries, 0);
  const json truth = sim_truth(viewer());
  const int collisions = collisions_before_resets + truth.at("collisions").get<int>();
  EXPECT_EQ(collisions, 0);
  if (collisions > 0) {
    for (const auto& event : run_events(viewer(), run)) {
      if (event.value("kind", "") == "collision") std::cout << "  " << event.dump() << std::endl;
    }
  }

  // The run: 20 succeeded goals, nothing else, and 20 `goal` events saying so.
  const json current = current_run(viewer());
  ASSERT_TRUE(current.contains("goals")) << current.dump();
  EXPECT_EQ(current.at("goals").at("succeeded"), kGoals) << current.dump();
  EXPECT_EQ(current.at("goals").at("failed"), 0) << current.dump();
  EXPECT_EQ(current.at("goals").at("canceled"), 0) << current.dump();
  int succeeded_events = 0;
  for (const auto& event : run_events(viewer(), run)) {
    if (event.value("kind", "") == "goal" && event.at("detail").is_object() &&
        event.at("detail").value("status", "") == "succeeded") {
      ++succeeded_events;
    }
  }
  EXPECT_EQ(succeeded_events, kGoals);
}

}  // namespace
}  // namespace mobot::testing

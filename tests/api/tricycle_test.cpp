// The tricycles of docs/algorithms.md R3 on their profiles (deploy/config/tricycle_t1.yaml and
// tricycle_t2.yaml, the yard world): 10 random goals each succeed with the configured planner
// (hybrid_astar) and pure pursuit, without a collision, and the simulator's truth stream never
// shows the body turning faster than 0.3 rad/s nor the steering past pi/4. Teleop is mapped onto
// the steering: a turn on the spot is not possible, a turn while driving is.
#include <atomic>
#include <iomanip>
#include <mutex>
#include <random>
#include <thread>

#include "support/goal_support.h"

namespace mobot::testing {
namespace {

constexpr int kYardGoals = 10;
constexpr double kYardClearance_m = 3.0;  // from every wall, building and container
constexpr double kYardMinTravel_m = 5.0;
constexpr double kYardGoalTimeout_s = 200.0;
constexpr double kYardPositionTolerance_m = 0.3;  // the profiles' goal tolerance
constexpr double kMaxTurnRate_radps = 0.3;
constexpr double kMaxSteer_rad = std::numbers::pi / 4;

// What the truth stream showed: the fastest turn (from consecutive true poses) and the largest
// true steering angle.
class TruthMonitor {
 public:
  TruthMonitor(std::uint16_t port, const std::string& token) : client_(port, token) {
    client_.send(json{{"op", "subscribe"}, {"topics", {"truth"}}});
    thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
  }
  double max_turn_rate() const { return max_turn_rate_.load(); }
  double max_steer() const { return max_steer_.load(); }
  int samples() const { return samples_.load(); }

 private:
  void run(std::stop_token stop) {
    std::optional<json> last;
    while (!stop.stop_requested()) {
      const auto frame = client_.read(std::chrono::milliseconds(200));
      if (!frame || !frame->text()) continue;
      const json message = frame->json();
      if (message.value("topic", "") != "truth") continue;
      const json& data = message.at("data");
      if (data.contains("steering_rad")) {
        max_steer_ = std::max(max_steer_.load(), std::abs(data.at("steering_rad").get<double>()));
      }
      if (last) {
        const double dt = message.at("t").get<double>() - last->at("t").get<double>();
        if (dt > 1e-6 && dt < 0.5) {
          const double dtheta = wrap_angle(data.at("pose").at("theta").get<double>() -
                                           last->at("data").at("pose").at("theta").get<double>());
          max_turn_rate_ = std::max(max_turn_rate_.load(), std::abs(dtheta) / dt);
        }
      }
      last = message;
      ++samples_;
    }
  }

  WsClient client_;
  std::atomic<double> max_turn_rate_{0.0};
  std::atomic<double> max_steer_{0.0};
  std::atomic<int> samples_{0};
  std::jthread thread_;
};

// The yard's buildings (drivers/sim/worlds/yard/world.yaml), which the map also shows.
template <const char* kConfig>
class TricycleSuite : public ServerSuite<TricycleSuite<kConfig>> {
 public:
  static MobotdProcess::Options server_options() {
    MobotdProcess::Options options;
    options.time_scale = 10.0;
    options.extra_args = {"--config",
                          std::string(MOBOT_SOURCE_ROOT) + "/deploy/config/" + kConfig + ".yaml"};
    return options;
  }

  static void random_goals(std::uint64_t seed) {
    using Base = ServerSuite<TricycleSuite<kConfig>>;
    const HttpClient viewer = Base::viewer();
    const json robot = robot_state(viewer);
    ASSERT_EQ(robot.at("kinematics"), kConfig);
    const GridMap map = fetch_active_map(viewer);
    ASSERT_TRUE(map.valid());
    TruthMonitor monitor(Base::port(), Base::viewer_token());
    std::mt19937_64 rng(seed);
    auto uniform = [&](double lo, double hi) {
      return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
    };
    json from = sim_truth(viewer).at("pose");
    int succeeded = 0;
    for (int i = 0; i < kYardGoals; ++i) {
      json target;
      for (int attempt = 0; attempt < 100000; ++attempt) {
        const double x = uniform(map.min_x(), map.max_x());
        const double y = uniform(map.min_y(), map.max_y());
        if (map.clearance(x, y, kYardClearance_m) < kYardClearance_m) continue;
        target = json{{"x", x}, {"y", y}};
        if (xy_distance(target, from) > kYardMinTravel_m) break;
      }
      from = target;
      const HttpReply reply = Base::operator_client().post("/api/v1/goals", target);
      ASSERT_EQ(reply.status, 201) << reply.body;
      EXPECT_EQ(reply.json().at("controller"), "pure_pursuit");
      const json goal = wait_goal_end(viewer, reply.json().at("id"), kYardGoalTimeout_s);
      const json truth = sim_truth(viewer);
      const double error = xy_distance(truth.at("pose"), target);
      std::cout << std::fixed << std::setprecision(2) << "[ " << kConfig << " goal " << i + 1
                << " ] " << pose_text(target) << " -> " << goal.value("status", "?") << " "
                << goal.value("reason", "") << " truth " << pose_text(truth.at("pose")) << " err "
                << error << " m, collisions " << truth.at("collisions") << std::endl;
      EXPECT_EQ(goal.value("status", ""), "succeeded") << goal.dump().substr(0, 300);
      EXPECT_LT(error, kYardPositionTolerance_m + 0.05);
      if (goal.value("status", "") == "succeeded") ++succeeded;
    }
    EXPECT_EQ(succeeded, kYardGoals);
    EXPECT_EQ(sim_truth(viewer).at("collisions"), 0);
    std::cout << "[ " << kConfig << " ] truth samples " << monitor.samples() << ", max |w| "
              << monitor.max_turn_rate() << " rad/s, max |steering| " << monitor.max_steer()
              << " rad" << std::endl;
    EXPECT_GT(monitor.samples(), 100);
    // The drive controller holds the limit on its wheel's count; the drive's own speed error
    // (2 %, wandering) and the tyres' slip on the floor come on top of it.
    EXPECT_LE(monitor.max_turn_rate(), kMaxTurnRate_radps * 1.1);
    EXPECT_LE(monitor.max_steer(), kMaxSteer_rad + 1e-6);
    EXPECT_GT(monitor.max_steer(), 0.3);  // it did steer
  }
};

constexpr char kT1[] = "tricycle_t1";
constexpr char kT2[] = "tricycle_t2";
using TricycleT1 = TricycleSuite<kT1>;
using TricycleT2 = TricycleSuite<kT2>;

TEST_F(TricycleT1, TenRandomGoalsWithPurePursuitAndNoCollision) { random_goals(20261204); }
TEST_F(TricycleT2, TenRandomGoalsWithPurePursuitAndNoCollision) { random_goals(20261205); }

TEST_F(TricycleT2, TeleopSteersAndCannotTurnOnTheSpot) {
  // On the spot: nothing moves (a tricycle has no such motion), and the reply says so.
  const HttpReply spin = operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.5}});
  ASSERT_EQ(spin.status, 200) << spin.body;
  EXPECT_EQ(spin.json().at("w"), 0.0);
  // Driving and turning: within 0.3 rad/s, the steering angle shows on /robot.
  const HttpReply turn = operator_client().post("/api/v1/teleop", json{{"v", 1.0}, {"w", 1.0}});
  ASSERT_EQ(turn.status, 200) << turn.body;
  EXPECT_LE(std::abs(turn.json().at("w").get<double>()), kMaxTurnRate_radps + 1e-9);
  EXPECT_GT(turn.json().at("w").get<double>(), 0.0);
  json robot;
  for (int i = 0; i < 20; ++i) {
    operator_client().post("/api/v1/teleop", json{{"v", 1.0}, {"w", 1.0}});
    robot = robot_state(viewer());
    if (robot.contains("steering_rad") && robot.at("steering_rad").get<double>() > 0.5) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(robot.contains("steering_rad")) << robot.dump();
  EXPECT_GT(robot.at("steering_rad").get<double>(), 0.5);
  EXPECT_LE(robot.at("steering_rad").get<double>(), kMaxSteer_rad + 1e-9);
  EXPECT_GT(robot.at("geometry").at("wheelbase_m").get<double>(), 1.8);
  operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}});
}

TEST_F(TricycleT1, LocalizesWithTheLandmarkEkf) {
  const json robot = robot_state(viewer());
  EXPECT_EQ(robot.at("localization").at("method").get<std::string>().rfind("landmark_ekf", 0), 0u)
      << robot.dump();
  // Its own covariance: small, from the beacons, not the placement's.
  const auto& cov = robot.at("localization").at("cov");
  EXPECT_LT(cov.at(0).get<double>(), 0.05);
  EXPECT_GT(cov.at(0).get<double>(), 0.0);
  const double error = xy_distance(robot.at("pose"), sim_truth(viewer()).at("pose"));
  EXPECT_LT(error, 0.3);
}

}  // namespace
}  // namespace mobot::testing

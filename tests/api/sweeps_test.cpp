// 3D sweeps (docs/api.md "3D sweeps"): POST/GET /api/v1/sweeps, the cloud as PLY and as a binary
// frame, the IPaBD obstacle map, the `cloud` stream topic, the bad paths, persistence across a
// kill, and the G2 lobby of docs/algorithms.md P2: after a sweep the robot goes to D through gate B
// (beam above it), and with the 3D layer switched off it takes gate A and hits the low beam.
#include <cstring>
#include <fstream>
#include <numbers>

#include "support/goal_support.h"

namespace mobot::testing {
namespace {

// g2_lobby (drivers/sim/worlds/g2_lobby): the wall with the gates spans y 3.0..3.3.
constexpr double kGateWallLow_y = 3.0;
constexpr double kGateWallHigh_y = 3.3;
constexpr double kGateA_half_width = 0.7;  // x -0.7 .. 0.7, beam z 0.8..1.0
constexpr double kGateB_min_x = -2.9;      // x -2.9 .. -1.5, beam z 1.7..1.9
constexpr double kGateB_max_x = -1.5;
constexpr double kGoalD_x = 0.0;
constexpr double kGoalD_y = 6.8;

MobotdProcess::Options lobby(const std::vector<std::string>& extra = {}) {
  MobotdProcess::Options options;
  options.time_scale = 20.0;
  options.extra_args = {"--world", "g2_lobby"};
  options.extra_args.insert(options.extra_args.end(), extra.begin(), extra.end());
  return options;
}

void expect_error(const HttpReply& reply, int status, const std::string& code) {
  EXPECT_EQ(reply.status, status) << reply.body;
  EXPECT_EQ(reply.error_code(), code) << reply.body;
}

// POSTs a sweep that must be accepted; returns its id.
std::int64_t start_sweep(const HttpClient& client, const json& body = json::object()) {
  const HttpReply reply = client.post("/api/v1/sweeps", body);
  EXPECT_EQ(reply.status, 201) << reply.body;
  if (reply.status != 201) return -1;
  EXPECT_EQ(reply.json().at("status"), "running");
  return reply.json().at("id").get<std::int64_t>();
}

// Polls the sweep until it is no longer running; returns it as last read.
json wait_sweep_end(const HttpClient& client, std::int64_t id, std::chrono::seconds cap = 60s) {
  json sweep;
  wait_until(
      [&] {
        const HttpReply reply = client.get("/api/v1/sweeps/" + std::to_string(id));
        if (reply.status != 200) return true;
        sweep = reply.json();
        return sweep.at("status") != "running";
      },
      cap);
  return sweep;
}

struct CloudFrame {
  std::uint16_t topic = 0;
  std::uint16_t header_bytes = 0;
  std::uint32_t sweep_id = 0;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  std::uint32_t flags = 0;
  std::uint32_t scans_done = 0;
  std::uint32_t scans_total = 0;
  std::vector<std::array<float, 4>> points;
};

template <class T>
T read_le(const std::string& bytes, std::size_t at) {
  T value{};
  std::memcpy(&value, bytes.data() + at, sizeof value);
  return value;
}

// README "Binary frames", cloud body. Fails the test on a malformed frame.
std::optional<CloudFrame> parse_cloud_frame(const std::string& bytes) {
  if (bytes.size() < 64 || bytes.compare(0, 4, "MBT1") != 0) {
    ADD_FAILURE() << "not a binary frame (" << bytes.size() << " bytes)";
    return std::nullopt;
  }
  CloudFrame frame;
  frame.topic = read_le<std::uint16_t>(bytes, 4);
  frame.header_bytes = read_le<std::uint16_t>(bytes, 6);
  const std::size_t body = frame.header_bytes;
  frame.sweep_id = read_le<std::uint32_t>(bytes, body);
  frame.first = read_le<std::uint32_t>(bytes, body + 4);
  frame.count = read_le<std::uint32_t>(bytes, body + 8);
  frame.flags = read_le<std::uint32_t>(bytes, body + 12);
  frame.scans_done = read_le<std::uint32_t>(bytes, body + 16);
  frame.scans_total = read_le<std::uint32_t>(bytes, body + 20);
  if (bytes.size() != body + 32 + frame.count * 16U) {
    ADD_FAILURE() << "cloud frame of " << bytes.size() << " bytes for " << frame.count << " points";
    return std::nullopt;
  }
  for (std::uint32_t i = 0; i < frame.count; ++i) {
    std::array<float, 4> p{};
    std::memcpy(p.data(), bytes.data() + body + 32 + i * 16U, 16);
    frame.points.push_back(p);
  }
  return frame;
}

class SweepsTest : public ServerSuite<SweepsTest> {
 public:
  static MobotdProcess::Options server_options() { return lobby(); }

 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    // No sweep of an earlier test may still be running.
    for (const auto& sweep : viewer().get("/api/v1/sweeps").json()) {
      if (sweep.at("status") == "running") wait_sweep_end(viewer(), sweep.at("id"));
    }
    ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  }

  static std::size_t sweep_count() { return viewer().get("/api/v1/sweeps").json().size(); }
};

TEST_F(SweepsTest, ASweepRunsToDoneWithItsCloudAndObstacleMap) {
  const std::int64_t id = start_sweep(operator_client(), json{{"period_s", 10}, {"step_deg", 1}});
  const json running = viewer().get("/api/v1/sweeps/" + std::to_string(id)).json();
  EXPECT_EQ(running.at("mode"), (json{{"period_s", 10.0}, {"step_deg", 1.0}, {"scans", 81}}));
  EXPECT_TRUE(running.at("started_t").is_number());
  EXPECT_FALSE(running.contains("ended_t"));
  // Only one at a time, and the refused one leaves no trace.
  const std::size_t before = sweep_count();
  expect_error(operator_client().post("/api/v1/sweeps", json::object()), 409, "sweep_running");
  EXPECT_EQ(sweep_count(), before);
  // No cloud before it is done.
  const HttpReply early = viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/cloud");
  if (early.status != 200) expect_error(early, 409, "sweep_not_done");

  const json done = wait_sweep_end(viewer(), id);
  ASSERT_EQ(done.at("status"), "done") << done.dump();
  EXPECT_EQ(done.at("scans_done"), 81);
  EXPECT_GT(done.at("ended_t").get<double>(), done.at("started_t").get<double>() + 9.0);
  // A closed lobby: every beam of 81 scans x 181 beams returns.
  EXPECT_EQ(done.at("points"), 81 * 181);

  const HttpReply ply = viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/cloud?format=ply");
  ASSERT_EQ(ply.status, 200);
  const std::string header = "ply\nformat binary_little_endian 1.0\n";
  ASSERT_EQ(ply.body.compare(0, header.size(), header), 0);
  EXPECT_NE(ply.body.find("element vertex 14661\n"), std::string::npos);
  const std::size_t end = ply.body.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(ply.body.size() - end - 11, 14661U * 16U);

  const HttpReply bin = viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/cloud?format=bin");
  ASSERT_EQ(bin.status, 200);
  const auto cloud = parse_cloud_frame(bin.body);
  ASSERT_TRUE(cloud);
  EXPECT_EQ(cloud->topic, 3);
  EXPECT_EQ(cloud->sweep_id, id);
  EXPECT_EQ(cloud->count, 14661U);
  EXPECT_EQ(cloud->flags & 1U, 1U);
  // The cloud shows the floor, gate A's low beam on the straight line to D, and nothing of the
  // gate-A opening below that beam (the robot's 2D laser sees it open).
  int floor = 0;
  int beam_a = 0;
  for (const auto& [x, y, z, intensity] : cloud->points) {
    EXPECT_GE(z, -0.1F);
    EXPECT_GE(intensity, 0.0F);
    EXPECT_LE(intensity, 1.0F);
    if (std::abs(z) < 0.05F) ++floor;
    if (std::abs(x) < kGateA_half_width && y > 2.95F && y < 3.35F && z > 0.75F && z < 1.05F) {
      ++beam_a;
    }
  }
  EXPECT_GT(floor, 500);
  EXPECT_GT(beam_a, 20);

  const HttpReply map = viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/obstacle_map");
  ASSERT_EQ(map.status, 200) << map.body;
  const json grid = map.json();
  EXPECT_NEAR(grid.at("resolution").get<double>(), 0.2, 1e-9) << "a = D / 3 with D = 0.6 m";
  const auto value_at = [&](double x, double y) {
    const int col =
        static_cast<int>(std::floor((x - grid.at("origin").at("x").get<double>()) / 0.2));
    const int row =
        static_cast<int>(std::floor((y - grid.at("origin").at("y").get<double>()) / 0.2));
    return grid.at("data")
        .at(static_cast<std::size_t>(row * grid.at("width").get<int>() + col))
        .get<int>();
  };
  EXPECT_EQ(value_at(0.0, 3.15), 100) << "gate A's beam is below the robot's height";
  EXPECT_EQ(value_at(-2.2, 3.15), 0) << "gate B's beam is above it";
  EXPECT_EQ(value_at(0.0, 1.5), 0) << "the floor between the robot and the gates";
}

TEST_F(SweepsTest, TheCloudStreamsProgressivelyWhileTheSweepRuns) {
  WsClient stream(port(), viewer_token());
  stream.send({{"op", "subscribe"}, {"topics", {"cloud"}}, {"encoding", "binary"}});
  ASSERT_TRUE(stream.read_until("subscribed").has_value());
  // A rate limit thins samples, never the chunks of a cloud.
  WsClient thinned(port(), viewer_token());
  thinned.send({{"op", "subscribe"}, {"topics", {"cloud", "pose"}}, {"max_rate_hz", 1}});
  ASSERT_TRUE(thinned.read_until("subscribed").has_value());
  const std::int64_t id = start_sweep(operator_client(), json{{"period_s", 10}, {"step_deg", 0.5}});
  std::uint32_t next_first = 0;
  std::uint32_t scans_seen = 0;
  bool last = false;
  while (!last) {
    const auto frame = stream.read_binary(10s);
    ASSERT_TRUE(frame.has_value()) << "the cloud stream stopped after " << scans_seen << " scans";
    const auto chunk = parse_cloud_frame(frame->payload);
    ASSERT_TRUE(chunk);
    ASSERT_EQ(chunk->sweep_id, id);
    EXPECT_EQ(chunk->first, next_first) << "chunks are contiguous";
    EXPECT_EQ(chunk->scans_total, 40U);
    EXPECT_EQ(chunk->scans_done, scans_seen + 1);
    EXPECT_LE(chunk->count, 361U);
    next_first += chunk->count;
    scans_seen = chunk->scans_done;
    last = (chunk->flags & 1U) != 0;
  }
  EXPECT_EQ(scans_seen, 40U);
  const json done = wait_sweep_end(viewer(), id);
  EXPECT_EQ(done.at("points").get<std::uint32_t>(), next_first);
  int thinned_chunks = 0;
  for (const auto& frame : thinned.read_all_for(500ms)) thinned_chunks += frame.binary() ? 1 : 0;
  EXPECT_EQ(thinned_chunks, 40);
  // The same data as JSON on request.
  WsClient json_stream(port(), viewer_token());
  json_stream.send({{"op", "subscribe"}, {"topics", {"cloud"}}, {"encoding", "json"}});
  ASSERT_TRUE(json_stream.read_until("subscribed").has_value());
  start_sweep(operator_client());
  const auto chunk = json_stream.read_until("cloud", 10s);
  ASSERT_TRUE(chunk.has_value());
  const json& data = chunk->at("data");
  EXPECT_EQ(data.at("first"), 0);
  EXPECT_EQ(data.at("scans_total"), 81);
  ASSERT_EQ(data.at("points").size(), data.at("count").get<std::size_t>());
  EXPECT_EQ(data.at("points").at(0).size(), 4U);
}

TEST_F(SweepsTest, BadRequestsAreRefusedAndChangeNothing) {
  const std::size_t before = sweep_count();
  expect_error(operator_client().post("/api/v1/sweeps", json{{"period_s", 20}}), 400,
               "invalid_mode");
  expect_error(operator_client().post("/api/v1/sweeps", json{{"step_deg", 2}}), 400,
               "invalid_mode");
  expect_error(operator_client().post("/api/v1/sweeps", json{{"step_deg", "fine"}}), 400,
               "invalid_field");
  expect_error(operator_client().post("/api/v1/sweeps", json{{"period_s", -10}}), 400,
               "invalid_field");
  expect_error(operator_client().post("/api/v1/sweeps", std::string(R"({"period_s": 1e999})")), 400,
               "malformed_json");
  expect_error(operator_client().post("/api/v1/sweeps", std::string("{\"period_s\":")), 400,
               "malformed_json");
  expect_error(viewer().post("/api/v1/sweeps", json::object()), 403, "forbidden");
  expect_error(anonymous().post("/api/v1/sweeps", json::object()), 401, "unauthorized");
  expect_error(HttpClient(port(), "wrong").get("/api/v1/sweeps"), 401, "unauthorized");
  EXPECT_EQ(sweep_count(), before);

  expect_error(viewer().get("/api/v1/sweeps/999999"), 404, "unknown_sweep");
  expect_error(viewer().get("/api/v1/sweeps/abc"), 404, "unknown_sweep");
  expect_error(viewer().get("/api/v1/sweeps/999999/cloud"), 404, "unknown_sweep");
  expect_error(viewer().get("/api/v1/sweeps/999999/obstacle_map"), 404, "unknown_sweep");
  expect_error(viewer().get("/api/v1/sweeps/1/colour"), 404, "not_found");
  expect_error(operator_client().post("/api/v1/sweeps/1", json::object()), 405,
               "method_not_allowed");
  const std::int64_t id = start_sweep(operator_client());
  wait_sweep_end(viewer(), id);
  expect_error(viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/cloud?format=xyz"), 400,
               "invalid_format");
}

TEST_F(SweepsTest, AResetEndsARunningSweepAsFailedAndEventsAreRecorded) {
  const std::int64_t id = start_sweep(operator_client(), json{{"period_s", 42}, {"step_deg", 1}});
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  const json failed = wait_sweep_end(viewer(), id);
  EXPECT_EQ(failed.at("status"), "failed");
  EXPECT_EQ(failed.at("reason"), "reset");
  expect_error(viewer().get("/api/v1/sweeps/" + std::to_string(id) + "/cloud"), 409,
               "sweep_not_done");
  // A new sweep may start at once.
  const std::int64_t next = start_sweep(operator_client());
  EXPECT_EQ(wait_sweep_end(viewer(), next).at("status"), "done");

  std::vector<std::string> statuses;
  for (const auto& event : run_events(viewer(), current_run_id(viewer()))) {
    if (event.at("kind") != "sweep") continue;
    const json& detail = event.at("detail");
    if (detail.at("id") == id || detail.at("id") == next) statuses.push_back(detail.at("status"));
  }
  EXPECT_EQ(statuses, (std::vector<std::string>{"running", "failed", "running", "done"}));
}

TEST_F(SweepsTest, AnAdminDeletesAFinishedSweepButNotARunningOne) {
  const std::int64_t id = start_sweep(operator_client(), json{{"period_s", 42}, {"step_deg", 1}});
  const std::string target = "/api/v1/sweeps/" + std::to_string(id);
  expect_error(admin().del(target), 409, "sweep_running");
  expect_error(operator_client().del(target), 403, "forbidden");
  expect_error(admin().del("/api/v1/sweeps/999999"), 404, "unknown_sweep");
  expect_error(admin().del("/api/v1/sweeps/abc"), 404, "unknown_sweep");
  EXPECT_EQ(viewer().get(target).json().at("status"), "running") << "the refusals changed nothing";
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  ASSERT_EQ(wait_sweep_end(viewer(), id).at("status"), "failed");
  const std::int64_t done = start_sweep(operator_client());
  ASSERT_EQ(wait_sweep_end(viewer(), done).at("status"), "done");

  for (const std::int64_t gone : {id, done}) {
    const std::string path = "/api/v1/sweeps/" + std::to_string(gone);
    const HttpReply deleted = admin().del(path);
    EXPECT_EQ(deleted.status, 204) << deleted.body;
    EXPECT_TRUE(deleted.body.empty());
    expect_error(viewer().get(path), 404, "unknown_sweep");
    expect_error(viewer().get(path + "/cloud"), 404, "unknown_sweep");
    expect_error(admin().del(path), 404, "unknown_sweep");
  }
  for (const auto& sweep : viewer().get("/api/v1/sweeps").json()) {
    EXPECT_NE(sweep.at("id"), id);
    EXPECT_NE(sweep.at("id"), done);
  }
}

// The route of a goal to D through the gate wall: the x where its path crosses the wall.
std::optional<double> gate_crossing_x(const json& goal) {
  for (const auto& point : goal.at("path")) {
    const double y = point.at(1).get<double>();
    if (y >= kGateWallLow_y && y <= kGateWallHigh_y) return point.at(0).get<double>();
  }
  // Waypoints may straddle the wall: interpolate the segment that crosses it.
  const auto& path = goal.at("path");
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double y0 = path[i - 1].at(1).get<double>();
    const double y1 = path[i].at(1).get<double>();
    if ((y0 - kGateWallLow_y) * (y1 - kGateWallLow_y) <= 0.0 && y0 != y1) {
      const double f = (kGateWallLow_y - y0) / (y1 - y0);
      return path[i - 1].at(0).get<double>() +
             f * (path[i].at(0).get<double>() - path[i - 1].at(0).get<double>());
    }
  }
  return std::nullopt;
}

void drive_to_d_through_gate_b(const HttpClient& client, const std::string& planner) {
  const int collisions_before = sim_truth(client).at("collisions");
  const HttpReply reply =
      client.post("/api/v1/goals", json{{"x", kGoalD_x}, {"y", kGoalD_y}, {"planner", planner}});
  ASSERT_EQ(reply.status, 201) << reply.body;
  const auto crossing = gate_crossing_x(reply.json());
  ASSERT_TRUE(crossing) << reply.body;
  EXPECT_GT(*crossing, kGateB_min_x) << planner << " does not go through gate B";
  EXPECT_LT(*crossing, kGateB_max_x) << planner << " does not go through gate B";
  const json goal = wait_goal_end(client, reply.json().at("id"), 150.0);
  EXPECT_EQ(goal.at("status"), "succeeded") << planner << ": " << goal.dump().substr(0, 300);
  const json truth = sim_truth(client);
  EXPECT_EQ(truth.at("collisions").get<int>(), collisions_before) << planner;
  EXPECT_LT(std::hypot(truth.at("pose").at("x").get<double>() - kGoalD_x,
                       truth.at("pose").at("y").get<double>() - kGoalD_y),
            0.15)
      << planner << " ended at " << pose_text(truth.at("pose"));
}

TEST_F(SweepsTest, AfterASweepGoalsToDGoThroughGateBWithAStarAndVoronoi) {
  const std::int64_t id = start_sweep(operator_client(), json{{"period_s", 10}, {"step_deg", 1}});
  ASSERT_EQ(wait_sweep_end(viewer(), id).at("status"), "done");
  drive_to_d_through_gate_b(operator_client(), "astar");
  // The 3D layer survives until the next sweep of the area: the robot goes back to S and the
  // Voronoi planner takes B as well without a new sweep.
  ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  drive_to_d_through_gate_b(operator_client(), "voronoi");
}

// The sweep's data outlives the process: a SIGKILL after it is done loses nothing, and a sweep
// the process was running when it died comes back as failed ("interrupted").
TEST(SweepsPersistenceTest, DoneSweepsSurviveAKillAndInterruptedOnesAreFailed) {
  const std::filesystem::path dir = MobotdProcess::make_temp_dir();
  MobotdProcess::Options options = lobby();
  options.data_dir = dir;
  std::int64_t done_id = 0;
  std::int64_t interrupted_id = 0;
  {
    MobotdProcess process(options);
    const HttpClient admin(process.port(), process.token());
    done_id = start_sweep(admin);
    ASSERT_EQ(wait_sweep_end(admin, done_id).at("status"), "done");
    interrupted_id = start_sweep(admin, json{{"period_s", 42}, {"step_deg", 0.25}});
    process.kill_hard();
  }
  MobotdProcess restarted(options);
  const HttpClient admin(restarted.port(), restarted.token());
  const json done = admin.get("/api/v1/sweeps/" + std::to_string(done_id)).json();
  EXPECT_EQ(done.at("status"), "done");
  EXPECT_EQ(done.at("points"), 81 * 181);
  const HttpReply cloud =
      admin.get("/api/v1/sweeps/" + std::to_string(done_id) + "/cloud?format=bin");
  ASSERT_EQ(cloud.status, 200);
  EXPECT_EQ(cloud.body.size(), 64U + 81U * 181U * 16U);
  const json interrupted = admin.get("/api/v1/sweeps/" + std::to_string(interrupted_id)).json();
  EXPECT_EQ(interrupted.at("status"), "failed");
  EXPECT_EQ(interrupted.at("reason"), "interrupted");
  std::filesystem::remove_all(dir);
}

// P2's "2D trap": without the 3D layer the planner sees gate A as open, the straight route goes
// through it, and the 3D collision check stops the robot at the beam.
class TwoDTrapTest : public ServerSuite<TwoDTrapTest> {
 public:
  static MobotdProcess::Options server_options() {
    const std::filesystem::path config =
        std::filesystem::temp_directory_path() / "mobot_two_d_trap.yaml";
    std::ofstream(config) << "sweeps:\n  obstacle_layer: false\n";
    return lobby({"--config", config.string()});
  }
};

TEST_F(TwoDTrapTest, WithoutThe3DLayerTheRobotTakesGateAAndHitsTheBeam) {
  const std::int64_t id = start_sweep(operator_client());
  ASSERT_EQ(wait_sweep_end(viewer(), id).at("status"), "done");
  const HttpReply reply =
      operator_client().post("/api/v1/goals", json{{"x", kGoalD_x}, {"y", kGoalD_y}});
  ASSERT_EQ(reply.status, 201) << reply.body;
  const auto crossing = gate_crossing_x(reply.json());
  ASSERT_TRUE(crossing);
  EXPECT_LT(std::abs(*crossing), kGateA_half_width) << "the 2D plan goes through gate A";
  const json goal = wait_goal_end(operator_client(), reply.json().at("id"), 150.0);
  EXPECT_EQ(goal.at("status"), "failed");
  EXPECT_EQ(goal.value("reason", ""), "collision");
  EXPECT_GE(sim_truth(viewer()).at("collisions").get<int>(), 1);
  EXPECT_LT(sim_truth(viewer()).at("pose").at("y").get<double>(), kGateWallLow_y)
      << "stopped at the beam";
  (void)std::numbers::pi;
}

}  // namespace
}  // namespace mobot::testing

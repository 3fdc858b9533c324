// The process: the ready line on --port 0, the first-start admin token, SIGTERM (exit 0, the run is
// closed) and SIGKILL (what was acknowledged survives a restart on the same data dir).
#include <sys/stat.h>

#include <fstream>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

struct TempDir {
  TempDir() : path(MobotdProcess::make_temp_dir()) {}
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::filesystem::path path;
};

MobotdProcess::Options options_in(const std::filesystem::path& data_dir) {
  MobotdProcess::Options options;
  options.data_dir = data_dir;
  return options;
}

HttpClient admin_of(const MobotdProcess& process) { return {process.port(), process.token()}; }

json find_run(const HttpClient& client, std::int64_t id) {
  const HttpReply reply = client.get("/api/v1/runs");
  EXPECT_EQ(reply.status, 200);
  for (const auto& run : reply.json()) {
    if (run.at("id") == id) return run;
  }
  return nullptr;
}

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

TEST(LifecycleTest, ReadyLineOnAnEphemeralPort) {
  MobotdProcess first;
  MobotdProcess second;
  EXPECT_NE(first.port(), 0);
  EXPECT_NE(second.port(), 0);
  EXPECT_NE(first.port(), second.port());
  EXPECT_LT(first.startup_time(), std::chrono::seconds(15));
  for (const auto* process : {&first, &second}) {
    const HttpReply reply = HttpClient(process->port(), "").get("/api/v1/health");
    EXPECT_EQ(reply.status, 200) << reply.body;
  }
}

TEST(LifecycleTest, InvalidFlagsFailWithoutAReadyLine) {
  for (const auto& args : {std::vector<std::string>{"--world", "atlantis"},
                           std::vector<std::string>{"--backend", "quantum"},
                           std::vector<std::string>{"--port", "70000"}}) {
    MobotdProcess::Options options;
    options.extra_args = args;
    EXPECT_THROW(MobotdProcess process(options), std::runtime_error) << args[0] << " " << args[1];
  }
}

TEST(LifecycleTest, SigtermClosesStreamsAndExitsZero) {
  MobotdProcess process;
  const HttpClient admin = admin_of(process);
  WsClient stream(process.port(), process.token());
  stream.send({{"op", "subscribe"}, {"topics", {"pose"}}});
  ASSERT_TRUE(stream.read_until("subscribed").has_value());
  ASSERT_EQ(admin.post("/api/v1/teleop", json{{"v", 0.5}, {"w", 0.0}, {"ttl_ms", 1000}}).status,
            200);

  EXPECT_EQ(process.terminate(), 0);
  // The stream ends (with a close frame, or at least the connection closes).
  bool closed = false;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline && !closed) {
    const auto frame = stream.read(1s);
    if (frame && frame->opcode == WsOp::kClose) {
      EXPECT_EQ(frame->close_code(), 1001);
      closed = true;
    }
    if (!stream.is_open()) closed = true;
  }
  EXPECT_TRUE(closed);
}

TEST(LifecycleTest, SigtermRightAfterTheReadyLineExitsZero) {
  // "Ready" includes handling SIGTERM: a supervisor may stop the server the moment it is up.
  for (int i = 0; i < 8; ++i) {
    MobotdProcess process;
    EXPECT_EQ(process.terminate(), 0)
        << "attempt " << i << ": SIGTERM killed mobotd instead of stopping it";
  }
}

TEST(LifecycleTest, SigtermClosesTheRunAndARestartOpensANewOne) {
  TempDir dir;
  std::int64_t first_run = -1;
  std::size_t samples = 0;
  {
    MobotdProcess process(options_in(dir.path));
    const HttpClient admin = admin_of(process);
    first_run = current_run_id(admin);
    ASSERT_GT(first_run, 0);
    ASSERT_TRUE(wait_robot_time(admin, 1.0));
    samples = admin.get("/api/v1/runs/" + std::to_string(first_run) + "/trajectory").json().size();
    EXPECT_GT(samples, 0U);
    const double before_stop = unix_now();
    EXPECT_EQ(process.terminate(), 0);
    EXPECT_GE(unix_now(), before_stop);
  }
  MobotdProcess restarted(options_in(dir.path));
  const HttpClient admin = admin_of(restarted);
  const json run = find_run(admin, first_run);
  ASSERT_TRUE(run.is_object()) << "the first run is gone";
  ASSERT_TRUE(run.contains("ended")) << "SIGTERM left the run open: " << run.dump();
  EXPECT_GE(run.at("ended").get<double>(), run.at("started").get<double>());
  EXPECT_LE(run.at("ended").get<double>(), unix_now() + 1.0);
  const std::int64_t second_run = current_run_id(admin);
  EXPECT_GT(second_run, first_run);
  const json trajectory =
      admin.get("/api/v1/runs/" + std::to_string(first_run) + "/trajectory").json();
  EXPECT_GE(trajectory.size(), samples);
}

TEST(LifecycleTest, SigkillKeepsTheFlushedTrajectoryAndStoredData) {
  TempDir dir;
  std::int64_t run_id = -1;
  json seen;
  std::int64_t map_id = -1;
  std::string token;
  {
    MobotdProcess process(options_in(dir.path));
    const HttpClient admin = admin_of(process);
    run_id = current_run_id(admin);
    ASSERT_TRUE(wait_robot_time(admin, 1.0));
    // Reading the trajectory returns what is stored: every sample in it was acknowledged.
    seen = admin.get("/api/v1/runs/" + std::to_string(run_id) + "/trajectory").json();
    ASSERT_GE(seen.size(), 10U);
    const HttpReply map = admin.post(
        "/api/v1/maps", map_import_body("before the kill", make_pgm(8, 8, test_map_pixels(8, 8))));
    ASSERT_EQ(map.status, 201);
    map_id = map.json().at("id").get<std::int64_t>();
    token = create_token(admin, "operator", "before the kill");
    process.kill_hard();
  }
  MobotdProcess restarted(options_in(dir.path));
  const HttpClient admin = admin_of(restarted);
  const json run = find_run(admin, run_id);
  ASSERT_TRUE(run.is_object());
  EXPECT_TRUE(run.contains("ended"))
      << "a killed run is not closed on the next start: " << run.dump();
  const json trajectory =
      admin.get("/api/v1/runs/" + std::to_string(run_id) + "/trajectory").json();
  ASSERT_GE(trajectory.size(), seen.size()) << "acknowledged trajectory samples were lost";
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_DOUBLE_EQ(trajectory[i].at("t").get<double>(), seen[i].at("t").get<double>()) << i;
  }
  EXPECT_EQ(admin.get("/api/v1/maps/" + std::to_string(map_id)).status, 200)
      << "an imported map was lost";
  EXPECT_EQ(admin.with_token(token).post("/api/v1/estop", json{{"engaged", false}}).status, 200)
      << "a created token was lost";
}

TEST(LifecycleTest, SigkillKeepsAnAcknowledgedEstopEvent) {
  TempDir dir;
  std::int64_t run_id = -1;
  double engaged_at = 0.0;
  {
    MobotdProcess process(options_in(dir.path));
    const HttpClient admin = admin_of(process);
    run_id = current_run_id(admin);
    ASSERT_TRUE(wait_robot_time(admin, 0.5));
    engaged_at = robot_time(admin);
    const HttpReply reply = admin.post("/api/v1/estop", json{{"engaged", true}});
    ASSERT_EQ(reply.status, 200);
    // The 200 acknowledged the e-stop: killing the server right now must not lose its event.
    process.kill_hard();
  }
  MobotdProcess restarted(options_in(dir.path));
  const HttpClient admin = admin_of(restarted);
  const json event = find_event(admin, run_id, "estop");
  ASSERT_FALSE(event.is_null()) << "the acknowledged estop event was lost by SIGKILL";
  EXPECT_EQ(event.at("detail").at("engaged"), true);
  EXPECT_GE(event.at("t").get<double>(), engaged_at);
}

TEST(LifecycleTest, SigkillWhileMappingLosesNoSavedMap) {
  TempDir dir;
  std::int64_t map_id = -1;
  {
    MobotdProcess process(options_in(dir.path));
    const HttpClient admin = admin_of(process);
    ASSERT_EQ(admin.post("/api/v1/mapping", json{{"action", "start"}}).status, 200);
    drive_for(admin, 0.0, 0.5, 2.0);
    const HttpReply saved =
        admin.post("/api/v1/mapping", json{{"action", "stop"}, {"save_as", "kept"}});
    ASSERT_EQ(saved.status, 200) << saved.body;
    map_id = saved.json().at("map_id").get<std::int64_t>();
    // A second session is under way when the server dies.
    ASSERT_EQ(admin.post("/api/v1/mapping", json{{"action", "start"}}).status, 200);
    drive_for(admin, 0.0, 0.5, 1.0);
    process.kill_hard();
  }
  MobotdProcess restarted(options_in(dir.path));
  const HttpClient admin = admin_of(restarted);
  const HttpReply map = admin.get("/api/v1/maps/" + std::to_string(map_id));
  ASSERT_EQ(map.status, 200) << "the saved map was lost";
  EXPECT_EQ(map.json().at("name"), "kept");
  EXPECT_EQ(map.json().at("active"), true);
  EXPECT_EQ(admin.get("/api/v1/maps/" + std::to_string(map_id) + "/map.pgm").status, 200);
  EXPECT_EQ(admin.get("/api/v1/mapping").json().at("mapping"), false);
}

TEST(LifecycleTest, FirstStartWritesTheAdminTokenFile) {
  TempDir dir;
  std::string token;
  {
    MobotdProcess process(options_in(dir.path));
    const auto file = dir.path / "admin.token";
    ASSERT_TRUE(std::filesystem::exists(file));
    struct stat info {};
    ASSERT_EQ(::stat(file.c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 0777, 0600) << std::oct << (info.st_mode & 0777);
    std::ifstream in(file);
    in >> token;
    ASSERT_FALSE(token.empty());
    EXPECT_NE(token, process.token());
    const HttpClient file_admin(process.port(), token);
    EXPECT_EQ(file_admin.get("/api/v1/tokens").status, 200)
        << "the admin.token is not an admin token";
    process.terminate();
  }
  // A restart keeps the stored token and does not write a new one.
  MobotdProcess restarted(options_in(dir.path));
  std::ifstream in(dir.path / "admin.token");
  std::string again;
  in >> again;
  EXPECT_EQ(again, token);
  EXPECT_EQ(HttpClient(restarted.port(), token).get("/api/v1/tokens").status, 200);
  // Only issued tokens work.
  EXPECT_EQ(HttpClient(restarted.port(), "never-issued").get("/api/v1/robot").status, 401);
}

TEST(LifecycleTest, RunNameFlagNamesTheRun) {
  MobotdProcess::Options options;
  options.extra_args = {"--run-name", "lifecycle run"};
  MobotdProcess process(options);
  const HttpClient admin = admin_of(process);
  const json run = find_run(admin, current_run_id(admin));
  ASSERT_TRUE(run.is_object());
  EXPECT_EQ(run.at("name"), "lifecycle run");
}

}  // namespace
}  // namespace mobot::testing

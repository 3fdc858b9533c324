// Runs of the current process: listing, trajectory (JSON and CSV, >= 10 Hz of robot time),
// events, distance, and unknown ids.
#include <sstream>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class RunsTest : public ServerSuite<RunsTest> {
 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    run_id_ = current_run_id(viewer());
    ASSERT_GT(run_id_, 0) << "no open run";
  }
  std::string run_path() const { return "/api/v1/runs/" + std::to_string(run_id_); }
  std::int64_t run_id_ = -1;
};

json trajectory(const HttpClient& client, const std::string& run_path) {
  const HttpReply reply = client.get(run_path + "/trajectory");
  EXPECT_EQ(reply.status, 200) << reply.body.substr(0, 200);
  return reply.status == 200 ? reply.json() : json::array();
}

TEST_F(RunsTest, TheCurrentRunIsListed) {
  const HttpReply reply = viewer().get("/api/v1/runs");
  ASSERT_EQ(reply.status, 200);
  const json runs = reply.json();
  ASSERT_TRUE(runs.is_array());
  json current;
  for (const auto& run : runs) {
    if (run.at("id") == run_id_) current = run;
  }
  ASSERT_TRUE(current.is_object());
  EXPECT_FALSE(current.contains("ended")) << current.dump();
  EXPECT_TRUE(current.at("name").is_string());
  EXPECT_FALSE(current.at("name").get<std::string>().empty());
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  EXPECT_LE(current.at("started").get<double>(), now + 1.0);
  EXPECT_GT(current.at("started").get<double>(), now - 600.0);
  EXPECT_GE(current.at("distance_m").get<double>(), 0.0);
  EXPECT_EQ(current.at("goals"), (json{{"succeeded", 0}, {"failed", 0}, {"canceled", 0}}));

  const HttpReply one = viewer().get(run_path());
  ASSERT_EQ(one.status, 200) << one.body;
  EXPECT_EQ(one.json().at("id"), run_id_);
  EXPECT_EQ(one.json().at("name"), current.at("name"));
  EXPECT_DOUBLE_EQ(one.json().at("started").get<double>(), current.at("started").get<double>());
}

TEST_F(RunsTest, TrajectoryIsSampledAtTenHertzOrMore) {
  const double t0 = robot_time(viewer());
  ASSERT_TRUE(wait_robot_time(viewer(), 3.0));
  const double t1 = robot_time(viewer());
  const json samples = trajectory(viewer(), run_path());
  ASSERT_TRUE(samples.is_array());
  int in_window = 0;
  double previous_t = -1.0;
  double max_gap = 0.0;
  for (const auto& sample : samples) {
    for (const char* key : {"t", "x", "y", "theta"})
      ASSERT_TRUE(sample.at(key).is_number()) << sample.dump();
    const double t = sample.at("t").get<double>();
    if (previous_t >= 0.0) {
      EXPECT_GT(t, previous_t) << "samples out of order";
      if (t >= t0 && t <= t1) max_gap = std::max(max_gap, t - previous_t);
    }
    previous_t = t;
    if (t >= t0 && t <= t1) ++in_window;
  }
  // >= 10 Hz over the 3 s (or more) of robot time waited.
  EXPECT_GE(in_window, static_cast<int>(10.0 * (t1 - t0)) - 1)
      << "between t " << t0 << " and " << t1;
  EXPECT_LE(max_gap, 0.1 + 1e-6);
  // What is recorded is readable at once (the current run is flushed on read).
  EXPECT_GE(previous_t, t1 - 0.25);
}

TEST_F(RunsTest, TrajectoryAsCsv) {
  ASSERT_TRUE(wait_robot_time(viewer(), 2.0));
  const json samples = trajectory(viewer(), run_path());
  const HttpReply reply = viewer().get(run_path() + "/trajectory?format=csv");
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(reply.header("content-type").rfind("text/csv", 0), 0U) << reply.header("content-type");
  std::istringstream in(reply.body);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,x,y,theta");
  std::size_t rows = 0;
  double previous_t = -1.0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    double t, x, y, theta;
    char c1, c2, c3;
    std::istringstream row(line);
    ASSERT_TRUE(row >> t >> c1 >> x >> c2 >> y >> c3 >> theta) << line;
    EXPECT_EQ(c1, ',');
    EXPECT_EQ(c2, ',');
    EXPECT_EQ(c3, ',');
    EXPECT_GT(t, previous_t);
    previous_t = t;
    ++rows;
  }
  // The CSV was read after the JSON: it has at least as many samples.
  EXPECT_GE(rows, samples.size());
  EXPECT_GE(rows, 20U);
  // ?format=json is the default.
  const HttpReply as_json = viewer().get(run_path() + "/trajectory?format=json");
  ASSERT_EQ(as_json.status, 200);
  EXPECT_TRUE(as_json.json().is_array());
}

TEST_F(RunsTest, UnknownTrajectoryFormatIs400) {
  for (const std::string format : {"xml", "CSV", "ply", "%00"}) {
    const HttpReply reply = viewer().get(run_path() + "/trajectory?format=" + format);
    EXPECT_EQ(reply.status, 400) << format;
    EXPECT_EQ(reply.error_code(), "invalid_format") << format;
  }
}

TEST_F(RunsTest, TrajectoryAndDistanceFollowTheRobot) {
  const double distance0 = viewer().get(run_path()).json().at("distance_m").get<double>();
  drive_for(operator_client(), 0.6, 0.0, 2.0);
  ASSERT_TRUE(wait_robot_time(viewer(), 1.0));  // stopped by the dead-man
  const json pose = robot_state(viewer()).at("pose");
  const json samples = trajectory(viewer(), run_path());
  ASSERT_FALSE(samples.empty());
  const json& last = samples.back();
  EXPECT_NEAR(last.at("x").get<double>(), pose.at("x").get<double>(), 0.05);
  EXPECT_NEAR(last.at("y").get<double>(), pose.at("y").get<double>(), 0.05);
  const double distance1 = viewer().get(run_path()).json().at("distance_m").get<double>();
  EXPECT_GT(distance1 - distance0, 0.5);
  EXPECT_LT(distance1 - distance0, 2.5);
}

TEST_F(RunsTest, EventsAreRecordedInOrder) {
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  const HttpReply reply = viewer().get(run_path() + "/events");
  ASSERT_EQ(reply.status, 200);
  const json events = reply.json();
  ASSERT_TRUE(events.is_array());
  ASSERT_GE(events.size(), 2U);
  double previous_t = -1.0;
  for (const auto& event : events) {
    ASSERT_TRUE(event.at("t").is_number()) << event.dump();
    ASSERT_TRUE(event.at("kind").is_string()) << event.dump();
    ASSERT_TRUE(event.contains("detail")) << event.dump();
    EXPECT_GE(event.at("t").get<double>(), previous_t);
    previous_t = event.at("t").get<double>();
  }
  // Each e-stop change, then its audit record (the command, committed before its reply).
  ASSERT_GE(events.size(), 4U);
  const json& engaged = events.at(events.size() - 4);
  const json& engaged_command = events.at(events.size() - 3);
  const json& released = events.at(events.size() - 2);
  const json& released_command = events.back();
  EXPECT_EQ(engaged.at("kind"), "estop");
  EXPECT_EQ(engaged.at("detail"), (json{{"engaged", true}}));
  EXPECT_EQ(engaged_command.at("kind"), "command");
  EXPECT_EQ(engaged_command.at("detail").at("command"), "POST /api/v1/estop");
  EXPECT_EQ(released.at("kind"), "estop");
  EXPECT_EQ(released.at("detail"), (json{{"engaged", false}}));
  EXPECT_EQ(released_command.at("kind"), "command");
  EXPECT_EQ(released_command.at("detail").at("request"), (json{{"engaged", false}}));
}

TEST_F(RunsTest, SensorsReportTheirRatesInRobotTime) {
  ASSERT_TRUE(wait_until([&] { return robot_time(viewer()) > 1.5; }, 30s));
  const json sensors = robot_state(viewer()).at("sensors");
  const std::map<std::string, double> expected = {
      {"encoders", 50.0}, {"laser", 10.0}, {"sonar", 10.0}, {"compass", 10.0}};
  for (const auto& [name, rate] : expected) {
    ASSERT_TRUE(sensors.contains(name)) << name << " in " << sensors.dump();
    EXPECT_TRUE(sensors.at(name).at("ok").get<bool>()) << name;
    EXPECT_NEAR(sensors.at(name).at("rate_hz").get<double>(), rate, 0.15 * rate) << name;
  }
}

TEST_F(RunsTest, UnknownRunsAre404) {
  for (const std::string id : {"999999", "0", "-1", "abc"}) {
    for (const std::string suffix : {"", "/trajectory", "/trajectory?format=csv", "/events"}) {
      const HttpReply reply = viewer().get("/api/v1/runs/" + id + suffix);
      EXPECT_EQ(reply.status, 404) << id << suffix;
      EXPECT_EQ(reply.error_code(), "unknown_run") << id << suffix;
    }
  }
}

}  // namespace
}  // namespace mobot::testing

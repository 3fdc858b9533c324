// A flood of REST and stream requests does not make the control loop late: 50 clients hammer
// /robot and the stream's ping for a few seconds while the robot drives, and the loop's own
// lateness metric stays below a quarter of the period at the 99th percentile and no tick is
// skipped: commands are posted to the loop, reads come from the published state (behind a
// priority-inheritance lock, so a preempted reader cannot hold the loop up), and the loop's thread
// runs with real-time priority. The test prints the worst tick and the worst lateness.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

double metric(const std::string& text, const std::string& name) {
  const std::regex line("(^|\n)" + name + " ([0-9.eE+-]+)");
  std::smatch match;
  if (!std::regex_search(text, match, line)) return std::nan("");
  return std::stod(match[2]);
}

TEST(ControlLoopLoad, FiftyClientsHammeringRestAndPingDoNotMakeTheLoopLate) {
  // As on a robot's PC: the loop's thread with real-time priority (the tests run as root).
  const std::filesystem::path config =
      std::filesystem::temp_directory_path() / "mobot_control_loop_load.yaml";
  std::ofstream(config) << "robot:\n  realtime_priority: 20\n";
  MobotdProcess::Options options;
  options.extra_args = {"--config", config.string()};
  // In real time, as on the robot: a tick every 20 ms of wall time.
  options.time_scale = 1.0;
  MobotdProcess process(options);
  const HttpClient admin(process.port(), process.token());
  const std::string before = admin.get("/metrics").body;
  ASSERT_FALSE(std::isnan(metric(before, "mobot_control_tick_lateness_seconds_p99")))
      << "the loop reports its lateness";
  const double late_ticks_before = metric(before, "mobot_control_late_ticks_total");

  constexpr int kRestClients = 40;
  constexpr int kStreamClients = 10;
  constexpr auto kDuration = std::chrono::seconds(4);
  std::atomic<bool> stop{false};
  std::atomic<long> requests{0};
  std::atomic<long> failures{0};
  std::vector<std::thread> clients;
  for (int i = 0; i < kRestClients; ++i) {
    clients.emplace_back([&] {
      const HttpClient client = admin;
      while (!stop) {
        const int status = client.get("/api/v1/robot").status;
        ++requests;
        if (status != 200) ++failures;
      }
    });
  }
  for (int i = 0; i < kStreamClients; ++i) {
    clients.emplace_back([&, i] {
      WsClient stream(process.port(), process.token());
      int id = 0;
      while (!stop) {
        stream.send({{"op", "ping"}, {"id", i * 1000000 + id++}});
        ++requests;
        if (!stream.read_until("pong", 2s)) ++failures;
        // Each stream is held to 100 messages a second (beyond that they are dropped): just
        // below it, ten of them.
        std::this_thread::sleep_for(11ms);
      }
    });
  }
  // The robot drives meanwhile: the tick does its full work.
  const auto deadline = std::chrono::steady_clock::now() + kDuration;
  while (std::chrono::steady_clock::now() < deadline) {
    admin.post("/api/v1/teleop", json{{"v", 0.2}, {"w", 0.3}, {"ttl_ms", 300}});
    std::this_thread::sleep_for(50ms);
  }
  stop = true;
  for (auto& client : clients) client.join();

  const std::string metrics = admin.get("/metrics").body;
  const double p99_s = metric(metrics, "mobot_control_tick_lateness_seconds_p99");
  const double late_ticks = metric(metrics, "mobot_control_late_ticks_total");
  EXPECT_EQ(metric(metrics, "mobot_control_realtime"), 1.0) << "the loop got its priority";
  std::printf(
      "%ld requests in %lld s, tick lateness p99 %.2f ms max %.2f ms, tick mean %.3f ms max %.3f "
      "ms, late ticks %.0f\n",
      requests.load(), static_cast<long long>(kDuration.count()), p99_s * 1e3,
      metric(metrics, "mobot_control_tick_lateness_seconds_max") * 1e3,
      metric(metrics, "mobot_control_tick_seconds_mean") * 1e3,
      metric(metrics, "mobot_control_tick_seconds_max") * 1e3, late_ticks - late_ticks_before);
  // Where a slow tick went: the slowest run of each stage.
  std::istringstream lines(metrics);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("mobot_stage_seconds_max", 0) == 0) std::printf("  %s\n", line.c_str());
  }
  EXPECT_EQ(failures.load(), 0);
  EXPECT_GT(requests.load(), 1000);
  // The loop keeps its 20 ms period: no tick skipped, and 99 % of them start within a quarter of
  // the period. The load runs on the same two cores as the loop; BENCHMARKS.md has the measured
  // lateness.
  EXPECT_EQ(late_ticks - late_ticks_before, 0.0);
  EXPECT_LT(p99_s, 5e-3);
}

}  // namespace
}  // namespace mobot::testing

// RestApi over fake ports: replies that wait come from the port's Completion, on any thread and
// exactly once; every refusal kind of the ports maps to its HTTP status with its code and message
// unchanged; goal planner and controller names are checked against the runtime's registries.
// Through a real HttpServer: a deferred reply is written by the session, in request order, and the
// connection goes on after it.
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/http_server.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "fake_ports.h"

namespace mobot::api {
namespace {

using boost::asio::ip::tcp;
using nlohmann::json;
using namespace std::chrono_literals;

// The responses a responder got, from whichever thread sent them.
class Replies {
 public:
  Responder responder() {
    return [this](Response response) {
      std::lock_guard lock(mutex_);
      responses_.push_back(std::move(response));
      arrived_.notify_all();
    };
  }

  std::size_t count() const {
    std::lock_guard lock(mutex_);
    return responses_.size();
  }

  // The first response, waiting up to 5 s for it.
  std::optional<Response> wait() {
    std::unique_lock lock(mutex_);
    if (!arrived_.wait_for(lock, 5s, [this] { return !responses_.empty(); })) return std::nullopt;
    return responses_.front();
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Response> responses_;
};

// The fake's tokens are the role names.
Request make_request(http::verb method, const std::string& target, const std::string& token,
                     const std::string& body = "") {
  Request request{method, target, 11};
  request.set(http::field::authorization, "Bearer " + token);
  request.body() = body;
  request.prepare_payload();
  return request;
}

Request post(const std::string& target, const std::string& body) {
  return make_request(http::verb::post, target, "operator", body);
}

json body_of(const Response& response) { return json::parse(response.body()); }

void expect_error(const Response& response, unsigned status, const std::string& code,
                  const std::string& message = "") {
  EXPECT_EQ(response.result_int(), status) << response.body();
  const json body = body_of(response);
  EXPECT_EQ(body.at("error").at("code"), code) << response.body();
  if (!message.empty()) {
    EXPECT_EQ(body.at("error").at("message"), message) << response.body();
  }
}

class RestApiTest : public ::testing::Test {
 protected:
  RestApiTest() : hub_(StreamOptions{}), api_(robot_.ports(), hub_, RestOptions{}) {}

  // The response to a request that must be answered before handle() returns.
  Response call(const Request& request) { return call(api_, request); }
  static Response call(RestApi& api, const Request& request) {
    Replies replies;
    api.handle(request, replies.responder());
    EXPECT_EQ(replies.count(), 1U) << request.target() << " was not answered at once";
    return replies.wait().value_or(Response{});
  }

  Response submit_goal(const std::string& body) { return call(post("/api/v1/goals", body)); }

  std::string metrics() { return api_.metrics_text(); }

  test::FakePorts robot_;
  StreamHub hub_;
  RestApi api_;
};

TEST_F(RestApiTest, ADeferredReplyArrivesWhenThePortCompletes) {
  robot_.answers.defer = true;
  Replies replies;
  api_.handle(post("/api/v1/estop", R"({"engaged":true})"), replies.responder());
  EXPECT_EQ(replies.count(), 0U) << "answered before the port completed";
  EXPECT_EQ(robot_.answers.run_pending(), 1U);
  const auto response = replies.wait();
  ASSERT_TRUE(response.has_value());
  EXPECT_EQ(response->result_int(), 200U);
  EXPECT_EQ(response->at(http::field::content_type), "application/json");
  EXPECT_EQ(body_of(*response), json({{"estop", true}}));
  EXPECT_NE(metrics().find(R"(mobot_http_responses_total{code="2xx"} 1)"), std::string::npos)
      << metrics();
}

TEST_F(RestApiTest, ACompletionCalledOnAnotherThreadReplies) {
  robot_.answers.defer = true;
  Replies replies;
  api_.handle(post("/api/v1/goals", R"({"x":1.5,"y":-2})"), replies.responder());
  std::thread control_loop([this] { robot_.answers.run_pending(); });
  control_loop.join();
  const auto response = replies.wait();
  ASSERT_TRUE(response.has_value());
  EXPECT_EQ(response->result_int(), 201U) << response->body();
  const json goal = body_of(*response);
  EXPECT_EQ(goal.at("target"), json({{"x", 1.5}, {"y", -2.0}}));
  EXPECT_EQ(goal.at("planner"), "astar");
  EXPECT_EQ(goal.at("controller"), "lyapunov");
}

TEST_F(RestApiTest, ADeferredResponseKeepsTheRequestsVersionAndConnection) {
  robot_.answers.defer = true;
  Request old_client = post("/api/v1/teleop", R"({"v":0.2,"w":0.1})");
  old_client.version(10);
  Request closing = post("/api/v1/localization/pose", R"({"x":1,"y":2,"theta":0.5})");
  closing.keep_alive(false);
  Replies old_replies;
  Replies closing_replies;
  api_.handle(old_client, old_replies.responder());
  api_.handle(closing, closing_replies.responder());
  EXPECT_EQ(robot_.answers.run_pending(), 2U);
  const auto old_response = old_replies.wait();
  ASSERT_TRUE(old_response.has_value());
  EXPECT_EQ(old_response->version(), 10U);
  EXPECT_FALSE(old_response->keep_alive());
  EXPECT_EQ(body_of(*old_response), json({{"v", 0.2}, {"w", 0.1}}));
  const auto closing_response = closing_replies.wait();
  ASSERT_TRUE(closing_response.has_value());
  EXPECT_EQ(closing_response->version(), 11U);
  EXPECT_FALSE(closing_response->keep_alive());
  EXPECT_EQ(body_of(*closing_response).at("pose"), json({{"x", 1.0}, {"y", 2.0}, {"theta", 0.5}}));
}

TEST_F(RestApiTest, EveryErrorKindMapsToItsStatusWithCodeAndMessageUnchanged) {
  const std::vector<std::pair<ErrorKind, unsigned>> kinds{{ErrorKind::kInvalid, 400},
                                                          {ErrorKind::kNotFound, 404},
                                                          {ErrorKind::kConflict, 409},
                                                          {ErrorKind::kImpossible, 422}};
  for (const auto& [kind, status] : kinds) {
    robot_.answers.refusal = DomainError{kind, "some_refusal", "refused: 'because' \"so\""};
    SCOPED_TRACE(status);
    // Through a Completion, and thrown by a method that answers at once.
    expect_error(call(post("/api/v1/estop", R"({"engaged":false})")), status, "some_refusal",
                 "refused: 'because' \"so\"");
    expect_error(call(make_request(http::verb::delete_, "/api/v1/maps/5", "admin")), status,
                 "some_refusal", "refused: 'because' \"so\"");
    expect_error(call(make_request(http::verb::get, "/api/v1/sweeps/2/cloud", "viewer")), status,
                 "some_refusal", "refused: 'because' \"so\"");
  }
  EXPECT_NE(metrics().find(R"(mobot_http_responses_total{code="4xx"} 12)"), std::string::npos)
      << metrics();
}

TEST_F(RestApiTest, ARefusalInADeferredReplyKeepsItsKind) {
  robot_.answers.defer = true;
  robot_.answers.refusal =
      DomainError{ErrorKind::kImpossible, "no_path", "no path to the goal (blocked)"};
  Replies replies;
  api_.handle(post("/api/v1/goals", R"({"x":1,"y":2})"), replies.responder());
  std::thread planner([this] { robot_.answers.run_pending(); });
  planner.join();
  const auto response = replies.wait();
  ASSERT_TRUE(response.has_value());
  expect_error(*response, 422, "no_path", "no path to the goal (blocked)");
}

TEST_F(RestApiTest, APortThatCompletesTwiceAndThenThrowsAnswersOnce) {
  robot_.answers.calls = 2;
  robot_.answers.throw_after_completing = true;
  const Response response = call(post("/api/v1/estop", R"({"engaged":true})"));
  EXPECT_EQ(response.result_int(), 200U) << response.body();
  EXPECT_NE(metrics().find(R"(mobot_http_responses_total{code="2xx"} 1)"), std::string::npos);
  EXPECT_NE(metrics().find(R"(mobot_http_responses_total{code="4xx"} 0)"), std::string::npos);
}

TEST_F(RestApiTest, ACompletionWhoseResponderFailsDoesNotThrowIntoThePort) {
  robot_.answers.defer = true;
  api_.handle(post("/api/v1/estop", R"({"engaged":true})"),
              [](Response) { throw std::runtime_error("the session is gone"); });
  EXPECT_NO_THROW(robot_.answers.run_pending());
}

TEST_F(RestApiTest, AResponseBuiltInACompletionMayStillRefuse) {
  robot_.answers.defer = true;
  Replies missing;
  Replies found;
  api_.handle(make_request(http::verb::get, "/api/v1/runs/99", "viewer"), missing.responder());
  api_.handle(make_request(http::verb::get, "/api/v1/runs/3", "viewer"), found.responder());
  EXPECT_EQ(robot_.answers.run_pending(), 2U);
  ASSERT_TRUE(missing.wait().has_value());
  expect_error(*missing.wait(), 404, "unknown_run", "no run with this id");
  ASSERT_TRUE(found.wait().has_value());
  EXPECT_EQ(body_of(*found.wait()).at("id"), 3);
}

TEST_F(RestApiTest, TheTransportsOwnRefusalsStayHttp) {
  expect_error(call(make_request(http::verb::post, "/api/v1/estop", "viewer", "{}")), 403,
               "forbidden");
  expect_error(call(make_request(http::verb::get, "/api/v1/estop", "operator")), 405,
               "method_not_allowed");
  expect_error(call(post("/api/v1/estop", "{")), 400, "malformed_json");
  expect_error(call(make_request(http::verb::get, "/api/v1/nothing", "viewer")), 404, "not_found");
  EXPECT_EQ(robot_.answers.pending(), 0U);
}

TEST_F(RestApiTest, AsynchronousEndpointsAnswerFromTheirCompletions) {
  EXPECT_EQ(body_of(call(post("/api/v1/maps/4/activate", ""))).at("active"), true);
  EXPECT_EQ(call(post("/api/v1/sweeps", "")).result_int(), 201U);
  EXPECT_EQ(body_of(call(post("/api/v1/sim/reset", ""))), json({{"ok", true}}));
  const Response obstacle = call(post("/api/v1/sim/obstacles", R"({"x":1,"y":2,"radius":0.3})"));
  EXPECT_EQ(obstacle.result_int(), 201U);
  EXPECT_EQ(body_of(obstacle), json({{"id", 7}}));
  EXPECT_EQ(
      call(make_request(http::verb::delete_, "/api/v1/sim/obstacles/7", "operator")).result_int(),
      204U);
  const Response csv =
      call(make_request(http::verb::get, "/api/v1/runs/3/trajectory?format=csv", "viewer"));
  EXPECT_EQ(csv.body(), "t,x,y,theta\n0.000,1.0000,2.0000,0.50000\n");
  EXPECT_EQ(csv.at(http::field::content_disposition), "attachment; filename=\"run-3.csv\"");
  expect_error(call(make_request(http::verb::delete_, "/api/v1/goals/9", "operator")), 404,
               "unknown_goal", "no goal with this id");
}

TEST_F(RestApiTest, SimEndpointsNeedTheSimulator) {
  RestApi hardware(robot_.ports(/*simulated=*/false), hub_, RestOptions{});
  expect_error(call(hardware, make_request(http::verb::get, "/api/v1/worlds", "viewer")), 404,
               "not_simulated");
  expect_error(call(hardware, post("/api/v1/sim/reset", "")), 404, "not_simulated");
  EXPECT_EQ(call(make_request(http::verb::get, "/api/v1/worlds", "viewer")).result_int(), 200U);
}

TEST_F(RestApiTest, GoalNamesTheRegistryKnowsAreAccepted) {
  robot_.control.planners = {"astar", "voronoi", "rrt"};
  robot_.control.controllers = {"lyapunov", "vfh"};
  const Response response = submit_goal(R"({"x":1,"y":2,"planner":"rrt","controller":"vfh"})");
  ASSERT_EQ(response.result_int(), 201U) << response.body();
  EXPECT_EQ(body_of(response).at("planner"), "rrt");
  EXPECT_EQ(body_of(response).at("controller"), "vfh");
  const Response defaults = submit_goal(R"({"x":1,"y":2})");
  EXPECT_EQ(body_of(defaults).at("planner"), "astar");
  EXPECT_EQ(body_of(defaults).at("controller"), "lyapunov");
}

TEST_F(RestApiTest, ContractNamesTheRegistryLacksAreUnsupported) {
  robot_.answers.defer = true;  // a refused goal never reaches the port
  robot_.control.planners = {"astar"};
  expect_error(submit_goal(R"({"x":1,"y":2,"controller":"dwa"})"), 422, "unsupported_controller",
               "the controller 'dwa' is not available in this build");
  expect_error(submit_goal(R"({"x":1,"y":2,"controller":"vfh"})"), 422, "unsupported_controller",
               "the controller 'vfh' is not available in this build");
  expect_error(submit_goal(R"({"x":1,"y":2,"planner":"voronoi"})"), 422, "unsupported_planner",
               "the planner 'voronoi' is not available in this build");
  EXPECT_EQ(robot_.answers.pending(), 0U);
}

TEST_F(RestApiTest, OtherGoalNamesAreInvalidFieldsListingTheRegistry) {
  robot_.answers.defer = true;
  expect_error(submit_goal(R"({"x":1,"y":2,"planner":"dijkstra"})"), 400, "invalid_field",
               "'planner' must be one of astar, voronoi");
  expect_error(submit_goal(R"({"x":1,"y":2,"planner":"ASTAR"})"), 400, "invalid_field");
  expect_error(submit_goal(R"({"x":1,"y":2,"planner":""})"), 400, "invalid_field");
  expect_error(submit_goal(R"({"x":1,"y":2,"planner":3})"), 400, "invalid_field");
  expect_error(submit_goal(R"({"x":1,"y":2,"controller":"mpc"})"), 400, "invalid_field",
               "'controller' must be one of lyapunov");
  robot_.control.controllers = {"lyapunov", "pure_pursuit"};
  expect_error(submit_goal(R"({"x":1,"y":2,"controller":"mpc"})"), 400, "invalid_field",
               "'controller' must be one of lyapunov, pure_pursuit");
  EXPECT_EQ(robot_.answers.pending(), 0U);
}

// A blocking HTTP client on the test thread.
class HttpClient {
 public:
  HttpClient(boost::asio::io_context& io, const tcp::endpoint& server) : socket_(io) {
    socket_.connect(server);
    const timeval timeout{5, 0};
    ::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }

  void send(const Request& request) { http::write(socket_, request); }
  void send_raw(const std::string& bytes) {
    boost::asio::write(socket_, boost::asio::buffer(bytes));
  }

  std::optional<Response> read() {
    Response response;
    boost::system::error_code error;
    http::read(socket_, buffer_, response, error);
    if (error) return std::nullopt;
    return response;
  }

  std::size_t available() { return socket_.available(); }
  void close() { socket_.close(); }

 private:
  tcp::socket socket_;
  boost::beast::flat_buffer buffer_;
};

std::string wire(const Request& request) {
  std::ostringstream out;
  out << request;
  return out.str();
}

class HttpSessionTest : public RestApiTest {
 protected:
  HttpSessionTest()
      : work_(boost::asio::make_work_guard(io_)), server_(io_, api_, hub_, robot_.ports()) {
    endpoint_ = server_.listen({"127.0.0.1", 0});
    for (int i = 0; i < 2; ++i) threads_.emplace_back([this] { io_.run(); });
  }

  // Keep-alive sessions wait for their next request: they are dropped with the io_context.
  ~HttpSessionTest() override {
    server_.stop();
    work_.reset();
    io_.stop();
    for (auto& thread : threads_) thread.join();
  }

  bool wait_for_pending(std::size_t count) {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (robot_.answers.pending() < count) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(1ms);
    }
    return true;
  }

  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  HttpServer server_;
  tcp::endpoint endpoint_;
  std::vector<std::thread> threads_;
  boost::asio::io_context client_io_;
};

TEST_F(HttpSessionTest, ADeferredReplyIsWrittenAndTheConnectionGoesOn) {
  robot_.answers.defer = true;
  HttpClient client(client_io_, endpoint_);
  for (const bool engaged : {true, false}) {
    client.send(post("/api/v1/estop", json({{"engaged", engaged}}).dump()));
    ASSERT_TRUE(wait_for_pending(1));
    std::thread control_loop([this] { robot_.answers.run_pending(); });
    control_loop.join();
    const auto response = client.read();
    ASSERT_TRUE(response.has_value());
    EXPECT_EQ(response->result_int(), 200U);
    EXPECT_EQ(body_of(*response), json({{"estop", engaged}}));
  }
  client.send(make_request(http::verb::get, "/api/v1/health", "viewer"));
  const auto health = client.read();
  ASSERT_TRUE(health.has_value());
  EXPECT_EQ(body_of(*health).at("backend"), "fake");
}

TEST_F(HttpSessionTest, PipelinedRequestsAreAnsweredInOrder) {
  robot_.answers.defer = true;
  HttpClient client(client_io_, endpoint_);
  client.send_raw(wire(post("/api/v1/estop", R"({"engaged":true})")) +
                  wire(make_request(http::verb::get, "/api/v1/health", "viewer")));
  ASSERT_TRUE(wait_for_pending(1));
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(client.available(), 0U) << "the second request was answered before the first";
  robot_.answers.run_pending();
  const auto first = client.read();
  const auto second = client.read();
  ASSERT_TRUE(first.has_value() && second.has_value());
  EXPECT_EQ(body_of(*first), json({{"estop", true}}));
  EXPECT_EQ(body_of(*second).at("status"), "ok");
}

TEST_F(HttpSessionTest, AReplyAfterTheClientLeftIsHarmless) {
  robot_.answers.defer = true;
  {
    HttpClient client(client_io_, endpoint_);
    client.send(post("/api/v1/estop", R"({"engaged":true})"));
    ASSERT_TRUE(wait_for_pending(1));
    client.close();
  }
  std::this_thread::sleep_for(20ms);
  std::thread control_loop([this] { robot_.answers.run_pending(); });
  control_loop.join();
  robot_.answers.defer = false;
  HttpClient next(client_io_, endpoint_);
  next.send(post("/api/v1/estop", R"({"engaged":false})"));
  const auto response = next.read();
  ASSERT_TRUE(response.has_value());
  EXPECT_EQ(body_of(*response), json({{"estop", false}}));
}

TEST_F(RestApiTest, MappingStartsStopsAndSavesWithTheContractsBodies) {
  EXPECT_EQ(body_of(call(post("/api/v1/mapping", R"({"action":"start"})"))),
            json({{"mapping", true}}));
  const Response status = call(make_request(http::verb::get, "/api/v1/mapping", "viewer"));
  EXPECT_EQ(status.result_int(), 200U);
  EXPECT_EQ(body_of(status).at("mapping"), true);
  EXPECT_TRUE(body_of(status).contains("loop_closures"));
  EXPECT_EQ(body_of(call(post("/api/v1/mapping", R"({"action":"stop","save_as":"hall"})"))),
            json({{"mapping", false}, {"map_id", 5}}));
  EXPECT_EQ(robot_.mapping.last_save_as, "hall");
  EXPECT_EQ(body_of(call(post("/api/v1/mapping", R"({"action":"stop"})"))),
            json({{"mapping", false}}));
  EXPECT_FALSE(robot_.mapping.last_save_as.has_value());
}

TEST_F(RestApiTest, BadMappingRequestsAreRefusedBeforeThePort) {
  expect_error(call(post("/api/v1/mapping", R"({"action":"pause"})")), 400, "invalid_field");
  expect_error(call(post("/api/v1/mapping", R"({})")), 400, "missing_field");
  expect_error(call(post("/api/v1/mapping", R"({"action":"stop","save_as":""})")), 400,
               "invalid_field");
  expect_error(call(post("/api/v1/mapping", R"({"action":"stop","save_as":7})")), 400,
               "invalid_field");
  expect_error(call(post("/api/v1/mapping", "{nope")), 400, "malformed_json");
  expect_error(
      call(make_request(http::verb::post, "/api/v1/mapping", "viewer", R"({"action":"start"})")),
      403, "forbidden");
  EXPECT_FALSE(robot_.mapping.status.mapping);
}

TEST_F(RestApiTest, LocalizationMethodAndGlobalLocalization) {
  const Response global = call(post("/api/v1/localization/global", ""));
  EXPECT_EQ(global.result_int(), 202U);
  EXPECT_EQ(body_of(global), json({{"method", "particle_filter"}}));
  const Response chosen = call(make_request(http::verb::put, "/api/v1/localization/method",
                                            "operator", R"({"method":"odometry"})"));
  EXPECT_EQ(body_of(chosen), json({{"method", "odometry"}}));
  expect_error(call(make_request(http::verb::put, "/api/v1/localization/method", "operator",
                                 R"({"method":"slam"})")),
               400, "unknown_method");
  expect_error(call(make_request(http::verb::put, "/api/v1/localization/method", "operator",
                                 R"({"method":null})")),
               400, "missing_field");
  expect_error(call(make_request(http::verb::put, "/api/v1/localization/method", "viewer",
                                 R"({"method":"ekf"})")),
               403, "forbidden");
  EXPECT_EQ(robot_.localization.method, "odometry");
  robot_.answers.refusal = DomainError{ErrorKind::kConflict, "no_map", "no map is active"};
  expect_error(call(post("/api/v1/localization/global", "")), 409, "no_map");
}

TEST_F(RestApiTest, ZonesAreListedAddedAndDeleted) {
  const Response added =
      call(post("/api/v1/maps/1/zones", R"({"name":"stairs","polygon":[[0,0],[1,0],[1,1]]})"));
  EXPECT_EQ(added.result_int(), 201U) << added.body();
  EXPECT_EQ(body_of(added), json({{"id", 1}}));
  const Response listed = call(make_request(http::verb::get, "/api/v1/maps/1/zones", "viewer"));
  EXPECT_EQ(body_of(listed),
            json::parse(R"([{"id":1,"name":"stairs","polygon":[[0.0,0.0],[1.0,0.0],[1.0,1.0]]}])"));
  EXPECT_EQ(
      call(make_request(http::verb::delete_, "/api/v1/maps/1/zones/1", "operator")).result_int(),
      204U);
  expect_error(call(make_request(http::verb::get, "/api/v1/maps/9/zones", "viewer")), 404,
               "unknown_map");
  expect_error(call(make_request(http::verb::delete_, "/api/v1/maps/1/zones/x", "operator")), 404,
               "unknown_zone");
}

TEST_F(RestApiTest, MalformedPolygonsAreRefusedAndNothingIsStored) {
  for (const char* body :
       {R"({"polygon":[[0,0],[1,0]]})", R"({"polygon":"square"})",
        R"({"polygon":[[0,0],[1,0],[1]]})", R"({"polygon":[[0,0],[1,0],["a",1]]})",
        R"({"polygon":[[0,0],[1,0],[1,2e6]]})"}) {
    SCOPED_TRACE(body);
    expect_error(call(post("/api/v1/maps/1/zones", body)), 400, "invalid_polygon");
  }
  std::string big = R"({"polygon":[)";
  for (int i = 0; i < 257; ++i)
    big += (i ? "," : "") + std::string("[") + std::to_string(i) + ",0]";
  expect_error(call(post("/api/v1/maps/1/zones", big + "]}")), 400, "invalid_polygon");
  expect_error(call(post("/api/v1/maps/1/zones", R"({"name":"x"})")), 400, "missing_field");
  expect_error(call(post("/api/v1/maps/1/zones", R"({"polygon":[[0,0],[1,0],[1,1e400]]})")), 400,
               "malformed_json");
  EXPECT_TRUE(robot_.maps.zones.empty());
}

TEST_F(RestApiTest, KidnapMovesTheSimulatedRobotOnly) {
  EXPECT_EQ(call(post("/api/v1/sim/kidnap", R"({"x":1,"y":2,"theta":0.5})")).result_int(), 200U);
  EXPECT_EQ(robot_.sim.kidnapped_to, (geometry::Pose2D{1, 2, 0.5}));
  expect_error(call(post("/api/v1/sim/kidnap", R"({"x":1,"y":2})")), 400, "missing_field");
  robot_.sim.kidnapped_to.reset();
  expect_error(call(post("/api/v1/sim/kidnap", R"({"x":NaN,"y":2,"theta":0})")), 400,
               "malformed_json");
  EXPECT_FALSE(robot_.sim.kidnapped_to.has_value());
}

}  // namespace
}  // namespace mobot::api

namespace mobot::api {
namespace {

// The operator lock over REST: one person drives at a time; the lock is taken by acquire or by the
// first command, refused to another person with operator_busy, released by its holder, taken over
// by an admin; a malformed command, or one the robot refuses, does not take the lock.
TEST_F(RestApiTest, OnePersonDrivesAtATime) {
  const auto operator_post = [&](const std::string& token, const std::string& body) {
    return call(make_request(http::verb::post, "/api/v1/operator", token, body));
  };
  const auto holder = [&] {
    return body_of(call(make_request(http::verb::get, "/api/v1/operator", "viewer"))).at("holder");
  };
  const auto teleop = [&](const std::string& token, const std::string& body) {
    Replies replies;
    api_.handle(make_request(http::verb::post, "/api/v1/teleop", token, body),
                replies.responder(), ClientContext{11, "10.1.1.1:4000"});
    return replies.wait().value_or(Response{});
  };
  EXPECT_TRUE(holder().is_null());
  // A malformed command is refused before the lock: it stays free.
  expect_error(teleop("operator2", R"({"v":"fast"})"), 400, "invalid_field");
  EXPECT_TRUE(holder().is_null());
  // Nor does a command the robot refuses (e-stop engaged, say).
  robot_.answers.refusal = DomainError{ErrorKind::kConflict, "estop_engaged", "e-stop"};
  expect_error(teleop("operator2", R"({"v":0.1,"w":0})"), 409, "estop_engaged");
  EXPECT_TRUE(holder().is_null());
  robot_.answers.refusal.reset();
  // The first command takes it.
  EXPECT_EQ(teleop("operator", R"({"v":0.1,"w":0})").result_int(), 200U);
  const json held = holder();
  EXPECT_EQ(held.at("label"), "operator");
  EXPECT_EQ(held.at("token_id"), 2);
  EXPECT_EQ(held.at("role"), "operator");
  EXPECT_EQ(held.at("client_id"), 11);
  EXPECT_EQ(held.at("address"), "10.1.1.1:4000");
  EXPECT_GT(held.at("since").get<double>(), 1.6e9);
  // Somebody else is refused, for teleop, goals and the lock itself.
  expect_error(teleop("operator2", R"({"v":0.1,"w":0})"), 409, "operator_busy");
  expect_error(call(make_request(http::verb::post, "/api/v1/goals", "operator2",
                                 R"({"x":1,"y":1})")),
               409, "operator_busy");
  expect_error(operator_post("operator2", R"({"action":"acquire"})"), 409, "operator_busy");
  expect_error(operator_post("operator2", R"({"action":"release"})"), 409, "not_holder");
  EXPECT_EQ(holder().at("label"), "operator");
  // E-stop is never locked.
  EXPECT_EQ(call(make_request(http::verb::post, "/api/v1/estop", "operator2",
                              R"({"engaged":true})"))
                .result_int(),
            200U);
  // Bad requests: a viewer, an operator taking over, an unknown action.
  expect_error(operator_post("viewer", R"({"action":"acquire"})"), 403, "forbidden");
  expect_error(operator_post("operator2", R"({"action":"take_over"})"), 403, "forbidden");
  expect_error(operator_post("operator", R"({"action":"steal"})"), 400, "invalid_field");
  expect_error(operator_post("operator", R"({})"), 400, "missing_field");
  EXPECT_EQ(holder().at("label"), "operator");
  // An admin takes over; the former holder is refused; the admin releases it.
  const Response taken = operator_post("admin", R"({"action":"take_over"})");
  EXPECT_EQ(taken.result_int(), 200U) << taken.body();
  EXPECT_EQ(body_of(taken).at("holder").at("label"), "admin");
  expect_error(teleop("operator", R"({"v":0.1,"w":0})"), 409, "operator_busy");
  EXPECT_TRUE(body_of(operator_post("admin", R"({"action":"release"})")).at("holder").is_null());
  EXPECT_EQ(body_of(operator_post("operator2", R"({"action":"acquire"})")).at("holder").at("label"),
            "operator2");
}

}  // namespace
}  // namespace mobot::api

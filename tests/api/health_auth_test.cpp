// Health, authentication, roles, tokens, unknown paths and wrong methods.
#include "support/api_test.h"

namespace mobot::testing {
namespace {

class HealthAuthTest : public ServerSuite<HealthAuthTest> {};

struct Call {
  std::string method;
  std::string target;
  std::string body;
};

std::string describe(const Call& call) { return call.method + " " + call.target; }

// Every protected endpoint with a body that would be valid, so that only the token decides.
std::vector<Call> protected_calls() {
  return {
      {"GET", "/metrics", ""},
      {"GET", "/api/v1/openapi.json", ""},
      {"GET", "/api/v1/robot", ""},
      {"POST", "/api/v1/teleop", R"({"v":0.5,"w":0})"},
      {"POST", "/api/v1/estop", R"({"engaged":true})"},
      {"GET", "/api/v1/maps", ""},
      {"POST", "/api/v1/maps",
       map_import_body("unauthorised", make_pgm(4, 4, test_map_pixels(4, 4))).dump()},
      {"GET", "/api/v1/maps/1", ""},
      {"DELETE", "/api/v1/maps/1", ""},
      {"POST", "/api/v1/maps/1/activate", ""},
      {"GET", "/api/v1/maps/1/image", ""},
      {"GET", "/api/v1/maps/1/map.pgm", ""},
      {"GET", "/api/v1/maps/1/map.yaml", ""},
      {"GET", "/api/v1/runs", ""},
      {"GET", "/api/v1/runs/1", ""},
      {"GET", "/api/v1/runs/1/trajectory", ""},
      {"GET", "/api/v1/runs/1/trajectory?format=csv", ""},
      {"GET", "/api/v1/runs/1/events", ""},
      {"GET", "/api/v1/worlds", ""},
      {"GET", "/api/v1/sim/truth", ""},
      {"POST", "/api/v1/sim/reset", R"({"pose":{"x":5,"y":7.5}})"},
      {"PUT", "/api/v1/sim/clock", R"({"time_scale":50})"},
      {"POST", "/api/v1/sim/obstacles", R"({"x":5,"y":7.5,"radius":0.3})"},
      {"DELETE", "/api/v1/sim/obstacles/1", ""},
      {"GET", "/api/v1/tokens", ""},
      {"POST", "/api/v1/tokens", R"({"role":"admin"})"},
      {"DELETE", "/api/v1/tokens/1", ""},
      {"GET", "/api/v1/whoami", ""},
  };
}

TEST_F(HealthAuthTest, HealthNeedsNoToken) {
  const HttpReply reply = anonymous().get("/api/v1/health");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.header("content-type"), "application/json");
  EXPECT_EQ(reply.header("strict-transport-security"), "") << "HSTS only over TLS (tls_test.cpp)";
  const json body = reply.json();
  EXPECT_EQ(body.at("status"), "ok");
  EXPECT_EQ(body.at("backend"), "sim");
  ASSERT_TRUE(body.at("version").is_string());
  EXPECT_FALSE(body.at("version").get<std::string>().empty());
  ASSERT_TRUE(body.at("uptime_s").is_number());
  EXPECT_GE(body.at("uptime_s").get<double>(), 0.0);
  EXPECT_LT(body.at("uptime_s").get<double>(), 600.0);

  // A wrong token does not matter for health.
  EXPECT_EQ(anonymous().request("GET", "/api/v1/health", "", "not-a-token").status, 200);
}

TEST_F(HealthAuthTest, HealthUptimeAdvances) {
  const double first = anonymous().get("/api/v1/health").json().at("uptime_s").get<double>();
  std::this_thread::sleep_for(50ms);
  const double second = anonymous().get("/api/v1/health").json().at("uptime_s").get<double>();
  EXPECT_GT(second, first);
}

TEST_F(HealthAuthTest, HealthRefusesOtherMethods) {
  for (const std::string method : {"POST", "PUT", "DELETE"}) {
    const HttpReply reply = admin().request(method, "/api/v1/health", "");
    EXPECT_EQ(reply.status, 405) << method;
    EXPECT_EQ(reply.error_code(), "method_not_allowed") << method;
  }
}

TEST_F(HealthAuthTest, EveryProtectedEndpointRefusesAMissingToken) {
  for (const auto& call : protected_calls()) {
    const HttpReply reply = anonymous().request(call.method, call.target, call.body, "");
    EXPECT_EQ(reply.status, 401) << describe(call) << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), "unauthorized") << describe(call);
  }
}

TEST_F(HealthAuthTest, EveryProtectedEndpointRefusesAWrongToken) {
  for (const auto& call : protected_calls()) {
    const HttpReply reply = anonymous().request(call.method, call.target, call.body, "wrong-token");
    EXPECT_EQ(reply.status, 401) << describe(call) << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), "unauthorized") << describe(call);
  }
}

TEST_F(HealthAuthTest, MalformedAuthorizationHeadersAreRefused) {
  const std::vector<std::string> headers = {
      "Basic dGVzdDp0ZXN0",
      "Bearer",
      "Bearer ",
      "Token " + server().token(),
      server().token(),
      "Bearer " + server().token() + "x",
      "Bearer " + std::string(5000, 'a'),
  };
  for (const auto& header : headers) {
    const HttpReply reply =
        anonymous().request_with_authorization("GET", "/api/v1/robot", "", header);
    EXPECT_EQ(reply.status, 401) << "Authorization: " << header.substr(0, 60);
  }
  // The token in the query string is for the WebSocket only.
  EXPECT_EQ(anonymous().get("/api/v1/robot?token=" + server().token()).status, 401);
}

TEST_F(HealthAuthTest, RefusedRequestsWithoutTokenChangeNothing) {
  // Whether the robot moved is the simulator's truth: the EKF estimate may settle by millimetres
  // on its own while the robot stands still.
  const json truth_before = viewer().get("/api/v1/sim/truth").json().at("pose");
  const int maps_before = static_cast<int>(viewer().get("/api/v1/maps").json().size());
  const int tokens_before = static_cast<int>(admin().get("/api/v1/tokens").json().size());
  for (const auto& call : protected_calls())
    anonymous().request(call.method, call.target, call.body, "");
  const json after = robot_state(viewer());
  EXPECT_FALSE(after.at("estop").get<bool>());
  EXPECT_NE(after.at("mode"), "teleop");
  EXPECT_NEAR(after.at("velocity").at("v").get<double>(), 0.0, 1e-3);
  const json truth_after = viewer().get("/api/v1/sim/truth").json().at("pose");
  EXPECT_NEAR(truth_after.at("x").get<double>(), truth_before.at("x").get<double>(), 1e-3);
  EXPECT_NEAR(truth_after.at("y").get<double>(), truth_before.at("y").get<double>(), 1e-3);
  EXPECT_EQ(viewer().get("/api/v1/maps").json().size(), maps_before);
  EXPECT_EQ(admin().get("/api/v1/tokens").json().size(), tokens_before);
  EXPECT_EQ(viewer().get("/api/v1/maps/1").status, 200) << "DELETE without a token removed map 1";
}

TEST_F(HealthAuthTest, ViewerCanReadEverything) {
  const auto active = viewer().get("/api/v1/maps").json();
  ASSERT_FALSE(active.empty());
  const std::string map = std::to_string(active.at(0).at("id").get<int>());
  const std::string run = std::to_string(current_run_id(viewer()));
  for (const std::string& target : std::vector<std::string>{
           "/api/v1/robot", "/api/v1/maps", "/api/v1/maps/" + map, "/api/v1/maps/" + map + "/image",
           "/api/v1/maps/" + map + "/map.pgm", "/api/v1/maps/" + map + "/map.yaml", "/api/v1/runs",
           "/api/v1/runs/" + run, "/api/v1/runs/" + run + "/trajectory",
           "/api/v1/runs/" + run + "/events", "/api/v1/worlds", "/api/v1/sim/truth", "/metrics",
           "/api/v1/openapi.json"}) {
    const HttpReply reply = viewer().get(target);
    EXPECT_EQ(reply.status, 200) << target << ": " << reply.body.substr(0, 200);
  }
}

TEST_F(HealthAuthTest, ViewerIsForbiddenOperatorEndpoints) {
  const HttpReply obstacle = operator_client().post("/api/v1/sim/obstacles",
                                                    json{{"x", 15.0}, {"y", 7.5}, {"radius", 0.2}});
  ASSERT_EQ(obstacle.status, 201) << obstacle.body;
  const std::string obstacle_id = std::to_string(obstacle.json().at("id").get<int>());
  const std::int64_t run = current_run_id(viewer());
  const auto events_before =
      viewer().get("/api/v1/runs/" + std::to_string(run) + "/events").json().size();

  const std::vector<Call> calls = {
      {"POST", "/api/v1/teleop", R"({"v":0.5,"w":0.5,"ttl_ms":1000})"},
      {"POST", "/api/v1/estop", R"({"engaged":true})"},
      {"POST", "/api/v1/maps/1/activate", ""},
      {"POST", "/api/v1/sim/reset", R"({"pose":{"x":5,"y":7.5}})"},
      {"PUT", "/api/v1/sim/clock", R"({"time_scale":0.5})"},
      {"POST", "/api/v1/sim/obstacles", R"({"x":5,"y":7.5,"radius":0.3})"},
      {"DELETE", "/api/v1/sim/obstacles/" + obstacle_id, ""},
  };
  for (const auto& call : calls) {
    const HttpReply reply = viewer().request(call.method, call.target, call.body);
    EXPECT_EQ(reply.status, 403) << describe(call) << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), "forbidden") << describe(call);
  }
  // Nothing happened: no e-stop, no motion, no reset event, the obstacle is still there.
  ASSERT_TRUE(wait_robot_time(viewer(), 0.3));
  const json state = robot_state(viewer());
  EXPECT_FALSE(state.at("estop").get<bool>());
  EXPECT_NEAR(state.at("velocity").at("v").get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(state.at("velocity").at("w").get<double>(), 0.0, 1e-3);
  const auto events = viewer().get("/api/v1/runs/" + std::to_string(run) + "/events").json();
  EXPECT_EQ(events.size(), events_before) << events.dump();
  EXPECT_EQ(operator_client().del("/api/v1/sim/obstacles/" + obstacle_id).status, 204)
      << "the viewer's DELETE removed the obstacle";
}

TEST_F(HealthAuthTest, OperatorMayUseOperatorEndpoints) {
  EXPECT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  EXPECT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  EXPECT_EQ(operator_client().post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 200);
  EXPECT_EQ(operator_client().post("/api/v1/maps/1/activate", "").status, 200);
}

TEST_F(HealthAuthTest, OperatorIsForbiddenAdminEndpoints) {
  // A map that is not active, so that only the role stops its deletion.
  const HttpReply imported = admin().post(
      "/api/v1/maps", map_import_body("admin only", make_pgm(8, 8, test_map_pixels(8, 8))));
  ASSERT_EQ(imported.status, 201) << imported.body;
  const std::string map_id = std::to_string(imported.json().at("id").get<int>());
  const auto maps_before = viewer().get("/api/v1/maps").json().size();
  const auto tokens_before = admin().get("/api/v1/tokens").json();

  const std::vector<Call> calls = {
      {"POST", "/api/v1/maps",
       map_import_body("operator import", make_pgm(8, 8, test_map_pixels(8, 8))).dump()},
      {"DELETE", "/api/v1/maps/" + map_id, ""},
      {"GET", "/api/v1/tokens", ""},
      {"POST", "/api/v1/tokens", R"({"role":"admin","label":"escalation"})"},
      {"DELETE", "/api/v1/tokens/1", ""},
  };
  for (const auto& call : calls) {
    for (const auto& client : {operator_client(), viewer()}) {
      const HttpReply reply = client.request(call.method, call.target, call.body);
      EXPECT_EQ(reply.status, 403) << describe(call) << ": " << reply.body;
      EXPECT_EQ(reply.error_code(), "forbidden") << describe(call);
    }
  }
  EXPECT_EQ(viewer().get("/api/v1/maps").json().size(), maps_before);
  EXPECT_EQ(viewer().get("/api/v1/maps/" + map_id).status, 200);
  EXPECT_EQ(admin().get("/api/v1/tokens").json(), tokens_before);
  EXPECT_EQ(admin().del("/api/v1/maps/" + map_id).status, 204);
}

TEST_F(HealthAuthTest, TokensCreateListRevoke) {
  const HttpReply created =
      admin().post("/api/v1/tokens", json{{"role", "viewer"}, {"label", "dashboard kiosk"}});
  ASSERT_EQ(created.status, 201) << created.body;
  const json token = created.json();
  EXPECT_EQ(token.at("role"), "viewer");
  ASSERT_TRUE(token.at("id").is_number_integer());
  const std::string secret = token.at("token").get<std::string>();
  EXPECT_GE(secret.size(), 16U);

  const HttpReply listed = admin().get("/api/v1/tokens");
  ASSERT_EQ(listed.status, 200);
  EXPECT_EQ(listed.body.find(secret), std::string::npos) << "the token list shows a token";
  bool found = false;
  for (const auto& entry : listed.json()) {
    for (const char* key : {"id", "role", "label", "created", "revoked"}) {
      EXPECT_TRUE(entry.contains(key)) << entry.dump();
    }
    if (entry.at("id") == token.at("id")) {
      found = true;
      EXPECT_EQ(entry.at("role"), "viewer");
      EXPECT_EQ(entry.at("label"), "dashboard kiosk");
      EXPECT_FALSE(entry.at("revoked").get<bool>());
    }
  }
  EXPECT_TRUE(found);

  const HttpClient kiosk = admin().with_token(secret);
  EXPECT_EQ(kiosk.get("/api/v1/robot").status, 200);
  EXPECT_EQ(kiosk.post("/api/v1/estop", json{{"engaged", true}}).status, 403);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token=" + secret), 101);

  const std::string id = std::to_string(token.at("id").get<int>());
  const HttpReply revoked = admin().del("/api/v1/tokens/" + id);
  EXPECT_EQ(revoked.status, 204) << revoked.body;
  EXPECT_TRUE(revoked.body.empty());
  EXPECT_EQ(kiosk.get("/api/v1/robot").status, 401) << "a revoked token still works";
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token=" + secret), 401);
  for (const auto& entry : admin().get("/api/v1/tokens").json()) {
    if (entry.at("id") == token.at("id")) {
      EXPECT_TRUE(entry.at("revoked").get<bool>());
    }
  }
}

TEST_F(HealthAuthTest, CreatedOperatorAndAdminTokensHaveTheirRoles) {
  const std::string op = create_token(admin(), "operator");
  const std::string adm = create_token(admin(), "admin");
  EXPECT_EQ(admin().with_token(op).post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  EXPECT_EQ(admin().with_token(op).get("/api/v1/tokens").status, 403);
  EXPECT_EQ(admin().with_token(adm).get("/api/v1/tokens").status, 200);
  // A token without a label is fine.
  const HttpReply unlabeled = admin().post("/api/v1/tokens", json{{"role", "viewer"}});
  EXPECT_EQ(unlabeled.status, 201) << unlabeled.body;
}

// A dashboard learns its own token at sign-in: the operator lock and the client list name tokens
// by id and label.
TEST_F(HealthAuthTest, WhoamiNamesTheCallersOwnToken) {
  const HttpReply made = admin().post(
      "/api/v1/tokens", json{{"role", "operator"}, {"label", "alice"}, {"expires_in_s", 3600}});
  ASSERT_EQ(made.status, 201) << made.body;
  const HttpClient alice = admin().with_token(made.json().at("token").get<std::string>());
  const HttpReply me = alice.get("/api/v1/whoami");
  ASSERT_EQ(me.status, 200) << me.body;
  EXPECT_EQ(me.json(), (json{{"token_id", made.json().at("id")},
                             {"label", "alice"},
                             {"role", "operator"},
                             {"expires_at", made.json().at("expires_at")}}));
  const json viewer_me = viewer().get("/api/v1/whoami").json();
  EXPECT_EQ(viewer_me.at("role"), "viewer");
  EXPECT_TRUE(viewer_me.at("expires_at").is_null());
  // The process's own admin token (--token) is id 0.
  const json admin_me = admin().get("/api/v1/whoami").json();
  EXPECT_EQ(admin_me.at("token_id"), 0);
  EXPECT_EQ(admin_me.at("role"), "admin");
  // A revoked token is nobody.
  ASSERT_EQ(admin().del("/api/v1/tokens/" + std::to_string(made.json().at("id").get<int>())).status,
            204);
  EXPECT_EQ(alice.get("/api/v1/whoami").status, 401);
}

TEST_F(HealthAuthTest, TokenRequestsAreValidated) {
  const auto tokens_before = admin().get("/api/v1/tokens").json().size();
  const std::vector<std::string> bodies = {
      R"({"role":"superuser"})",
      R"({"role":"Admin"})",
      R"({"role":""})",
      R"({"role":2})",
      R"({"role":null})",
      R"({})",
      R"({"label":"no role"})",
      R"({"role":"viewer","label":""})",
      R"({"role":"viewer","label":7})",
      R"({"role":"viewer","label":")" + std::string(200, 'x') + R"("})",
      R"({"role":"viewer")",
      R"(["viewer"])",
      R"(role=viewer)",
      "",
  };
  for (const auto& body : bodies) {
    const HttpReply reply = admin().post("/api/v1/tokens", body);
    EXPECT_EQ(reply.status, 400) << body << ": " << reply.body;
  }
  EXPECT_EQ(admin().get("/api/v1/tokens").json().size(), tokens_before);
}

TEST_F(HealthAuthTest, UnknownTokenIdsAre404) {
  for (const std::string id : {"999999", "0", "-1", "abc", "1.5"}) {
    const HttpReply reply = admin().del("/api/v1/tokens/" + id);
    EXPECT_EQ(reply.status, 404) << id;
    EXPECT_EQ(reply.error_code(), "unknown_token") << id;
  }
}

TEST_F(HealthAuthTest, UnknownPathsAre404) {
  for (const std::string target :
       {"/api/v1/nope", "/api/v2/robot", "/api/v1/robot/extra", "/api/v1", "/api", "/api/",
        "/api/v1/maps/1/unknown", "/api/v1/maps/1/image/extra", "/api/v1/runs/1/nope",
        "/api/v1/sim", "/api/v1/sim/nope", "/api/v1/sim/truth/x", "/api/v1/tokens/1/x",
        "/api/v1/goals/1/x", "/api/v1/localization", "/metrics/x", "/no-such-file.js"}) {
    const HttpReply reply = admin().get(target);
    EXPECT_EQ(reply.status, 404) << target << ": " << reply.body;
    EXPECT_TRUE(reply.json().contains("error")) << target;
  }
}

TEST_F(HealthAuthTest, WrongMethodsAre405) {
  const std::vector<Call> calls = {
      {"PUT", "/api/v1/robot", "{}"},
      {"POST", "/api/v1/robot", "{}"},
      {"POST", "/api/v1/whoami", "{}"},
      {"DELETE", "/api/v1/whoami", ""},
      {"GET", "/api/v1/teleop", ""},
      {"PUT", "/api/v1/teleop", R"({"v":0,"w":0})"},
      {"GET", "/api/v1/estop", ""},
      {"DELETE", "/api/v1/estop", ""},
      {"PATCH", "/api/v1/maps", "{}"},
      {"DELETE", "/api/v1/maps", ""},
      {"POST", "/api/v1/maps/1", "{}"},
      {"PUT", "/api/v1/maps/1", "{}"},
      {"GET", "/api/v1/maps/1/activate", ""},
      {"POST", "/api/v1/maps/1/image", ""},
      {"DELETE", "/api/v1/maps/1/map.pgm", ""},
      {"PUT", "/api/v1/maps/1/map.yaml", ""},
      {"POST", "/api/v1/runs", "{}"},
      {"DELETE", "/api/v1/runs/1", ""},
      {"POST", "/api/v1/runs/1/events", "{}"},
      {"POST", "/api/v1/worlds", "{}"},
      {"POST", "/api/v1/sim/truth", "{}"},
      {"GET", "/api/v1/sim/reset", ""},
      {"POST", "/api/v1/sim/clock", R"({"time_scale":1})"},
      {"GET", "/api/v1/sim/clock", ""},
      {"GET", "/api/v1/sim/obstacles", ""},
      {"GET", "/api/v1/sim/obstacles/1", ""},
      {"PUT", "/api/v1/tokens", "{}"},
      {"GET", "/api/v1/tokens/1", ""},
      {"POST", "/metrics", ""},
      {"POST", "/api/v1/openapi.json", "{}"},
      {"DELETE", "/api/v1/health", ""},
      {"POST", "/index.html", "{}"},
  };
  for (const auto& call : calls) {
    const HttpReply reply = admin().request(call.method, call.target, call.body);
    EXPECT_EQ(reply.status, 405) << describe(call) << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), "method_not_allowed") << describe(call);
  }
  // None of them did anything.
  EXPECT_FALSE(robot_state(viewer()).at("estop").get<bool>());
}

TEST_F(HealthAuthTest, ErrorsHaveTheContractShape) {
  const std::vector<HttpReply> replies = {
      anonymous().get("/api/v1/robot"),                         // 401
      viewer().post("/api/v1/estop", json{{"engaged", true}}),  // 403
      admin().get("/api/v1/maps/424242"),                       // 404
      admin().request("PUT", "/api/v1/robot", ""),              // 405
      admin().post("/api/v1/teleop", "{oops"),                  // 400
  };
  for (const auto& reply : replies) {
    EXPECT_GE(reply.status, 400);
    EXPECT_EQ(reply.header("content-type"), "application/json") << reply.status;
    const json body = json::parse(reply.body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << reply.body;
    ASSERT_TRUE(body.contains("error")) << reply.body;
    ASSERT_TRUE(body["error"].is_object());
    ASSERT_TRUE(body["error"]["code"].is_string()) << reply.body;
    ASSERT_TRUE(body["error"]["message"].is_string()) << reply.body;
    const std::string code = body["error"]["code"];
    EXPECT_FALSE(code.empty());
    for (const char c : code)
      EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || c == '_') << code;
    EXPECT_FALSE(body["error"]["message"].get<std::string>().empty());
  }
}

TEST_F(HealthAuthTest, MetricsArePrometheusText) {
  const HttpReply reply = viewer().get("/metrics");
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(reply.header("content-type").rfind("text/plain", 0), 0U)
      << reply.header("content-type");
  for (const char* name : {"mobot_http_responses_total{code=\"2xx\"}", "mobot_stream_clients",
                           "mobot_stream_frames_dropped_total", "mobot_uptime_seconds",
                           "# TYPE mobot_http_responses_total counter"}) {
    EXPECT_NE(reply.body.find(name), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace mobot::testing

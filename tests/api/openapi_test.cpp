// The served OpenAPI document: valid OpenAPI 3, the same as api/openapi.json, documents every
// endpoint the API tests use, and every operation it documents is served with the statuses it
// lists.
#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class OpenApiTest : public ServerSuite<OpenApiTest> {
 protected:
  static json document() {
    const HttpReply reply = viewer().get("/api/v1/openapi.json");
    EXPECT_EQ(reply.status, 200);
    return json::parse(reply.body, nullptr, false);
  }
};

std::vector<std::string> segments(std::string_view path) {
  path = path.substr(0, path.find('?'));
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= path.size()) {
    const auto slash = path.find('/', at);
    const std::string_view part =
        path.substr(at, slash == std::string_view::npos ? path.npos : slash - at);
    if (!part.empty()) out.emplace_back(part);
    if (slash == std::string_view::npos) break;
    at = slash + 1;
  }
  return out;
}

// The documented path template that `target` falls under, or "".
std::string match_path(const json& doc, const std::string& target) {
  const auto wanted = segments(target);
  for (const auto& [path, item] : doc.at("paths").items()) {
    const auto pattern = segments(path);
    if (pattern.size() != wanted.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < pattern.size() && same; ++i) {
      const bool parameter =
          pattern[i].size() > 2 && pattern[i].front() == '{' && pattern[i].back() == '}';
      same = parameter || pattern[i] == wanted[i];
    }
    if (same) return path;
  }
  return "";
}

std::string lowercase(std::string text) {
  for (auto& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// A request, who sends it, and the status the server must answer.
struct StatusCase {
  std::string method;
  std::string target;
  std::string body;
  HttpClient client;
  int status;
};

// Each request gets its status, and the document lists that status for the operation.
void expect_statuses_documented(const json& doc, const std::vector<StatusCase>& cases) {
  for (const auto& test : cases) {
    const HttpReply reply = test.client.request(test.method, test.target, test.body);
    EXPECT_EQ(reply.status, test.status) << test.method << " " << test.target << ": " << reply.body;
    const std::string path = match_path(doc, test.target);
    ASSERT_FALSE(path.empty()) << test.target;
    const json& responses = doc.at("paths").at(path).at(lowercase(test.method)).at("responses");
    EXPECT_TRUE(responses.contains(std::to_string(reply.status)))
        << test.method << " " << path << " answers " << reply.status << " but does not document it";
  }
}

const std::vector<std::string> kMethods = {"get", "post", "put", "delete", "patch"};

TEST_F(OpenApiTest, ServedDocumentIsOpenApi3) {
  const HttpReply reply = viewer().get("/api/v1/openapi.json");
  ASSERT_EQ(reply.status, 200);
  EXPECT_EQ(reply.header("content-type"), "application/json");
  const json doc = json::parse(reply.body, nullptr, false);
  ASSERT_FALSE(doc.is_discarded()) << "not JSON";
  ASSERT_TRUE(doc.at("openapi").is_string());
  EXPECT_EQ(doc.at("openapi").get<std::string>().rfind("3.", 0), 0U) << doc.at("openapi");
  EXPECT_TRUE(doc.at("info").at("title").is_string());
  EXPECT_TRUE(doc.at("info").at("version").is_string());
  ASSERT_TRUE(doc.at("paths").is_object());
  EXPECT_GE(doc.at("paths").size(), 20U);
  const json& bearer = doc.at("components").at("securitySchemes").at("bearerAuth");
  EXPECT_EQ(bearer.at("type"), "http");
  EXPECT_EQ(bearer.at("scheme"), "bearer");
  EXPECT_EQ(doc.at("security"), json::parse(R"([{"bearerAuth":[]}])"));
  // The error body of the contract.
  const json& error = doc.at("components").at("schemas").at("Error");
  EXPECT_EQ(error.at("required"), json({"error"}));
  EXPECT_EQ(error.at("properties").at("error").at("required"), json({"code", "message"}));
}

TEST_F(OpenApiTest, ServedDocumentIsTheSourceFile) {
  std::ifstream in(MOBOT_OPENAPI_FILE);
  ASSERT_TRUE(in.good()) << MOBOT_OPENAPI_FILE;
  std::stringstream text;
  text << in.rdbuf();
  const json source = json::parse(text.str(), nullptr, false);
  ASSERT_FALSE(source.is_discarded()) << "api/openapi.json is not valid JSON";
  EXPECT_EQ(document(), source) << "the binary serves a stale OpenAPI document: rebuild";
}

TEST_F(OpenApiTest, DocumentNeedsAToken) {
  EXPECT_EQ(anonymous().get("/api/v1/openapi.json").status, 401);
}

TEST_F(OpenApiTest, ReferencesResolve) {
  const json doc = document();
  std::vector<std::string> refs;
  std::function<void(const json&)> walk = [&](const json& node) {
    if (node.is_object()) {
      for (const auto& [key, value] : node.items()) {
        if (key == "$ref" && value.is_string()) refs.push_back(value);
        walk(value);
      }
    } else if (node.is_array()) {
      for (const auto& value : node) walk(value);
    }
  };
  walk(doc);
  EXPECT_GT(refs.size(), 20U);
  for (const auto& ref : refs) {
    ASSERT_EQ(ref.rfind("#/", 0), 0U) << ref;
    EXPECT_NO_THROW(doc.at(json::json_pointer(ref.substr(1)))) << "dangling $ref " << ref;
  }
}

TEST_F(OpenApiTest, EveryEndpointTheTestsUseIsDocumented) {
  const json doc = document();
  // Every method and path the API tests call (ids are placeholders).
  const std::vector<std::pair<std::string, std::string>> used = {
      {"GET", "/api/v1/health"},
      {"GET", "/api/v1/robot"},
      {"POST", "/api/v1/teleop"},
      {"POST", "/api/v1/estop"},
      {"GET", "/api/v1/goals"},
      {"POST", "/api/v1/goals"},
      {"GET", "/api/v1/goals/5"},
      {"DELETE", "/api/v1/goals/5"},
      {"POST", "/api/v1/localization/pose"},
      {"GET", "/api/v1/maps"},
      {"POST", "/api/v1/maps"},
      {"GET", "/api/v1/maps/7"},
      {"DELETE", "/api/v1/maps/7"},
      {"POST", "/api/v1/maps/7/activate"},
      {"GET", "/api/v1/maps/7/image"},
      {"GET", "/api/v1/maps/7/map.pgm"},
      {"GET", "/api/v1/maps/7/map.yaml"},
      {"GET", "/api/v1/runs"},
      {"GET", "/api/v1/runs/3"},
      {"GET", "/api/v1/runs/3/trajectory?format=csv"},
      {"GET", "/api/v1/runs/3/events"},
      {"GET", "/api/v1/worlds"},
      {"GET", "/api/v1/sim/truth"},
      {"POST", "/api/v1/sim/reset"},
      {"PUT", "/api/v1/sim/clock"},
      {"POST", "/api/v1/sim/obstacles"},
      {"DELETE", "/api/v1/sim/obstacles/2"},
      {"GET", "/api/v1/tokens"},
      {"POST", "/api/v1/tokens"},
      {"DELETE", "/api/v1/tokens/4"},
      {"GET", "/api/v1/stream?token=x"},
      {"GET", "/api/v1/openapi.json"},
      {"GET", "/metrics"},
  };
  for (const auto& [method, target] : used) {
    const std::string path = match_path(doc, target);
    ASSERT_FALSE(path.empty()) << target << " is not documented";
    EXPECT_TRUE(doc.at("paths").at(path).contains(lowercase(method)))
        << method << " " << path << " is not documented";
  }
  // The trajectory format and the stream token are documented parameters.
  const json& trajectory = doc.at("paths").at("/api/v1/runs/{id}/trajectory").at("get");
  EXPECT_NE(trajectory.at("parameters").dump().find("\"format\""), std::string::npos);
  const json& stream = doc.at("paths").at("/api/v1/stream").at("get");
  EXPECT_NE(stream.at("parameters").dump().find("\"token\""), std::string::npos);
  EXPECT_TRUE(stream.at("responses").contains("101"));
  EXPECT_TRUE(stream.at("responses").contains("401"));
}

TEST_F(OpenApiTest, EveryDocumentedOperationIsServedWithADocumentedStatus) {
  const json doc = document();
  int checked = 0;
  for (const auto& [path, item] : doc.at("paths").items()) {
    for (const auto& method : kMethods) {
      if (!item.contains(method)) continue;
      const json& operation = item.at(method);
      if (path == "/api/v1/stream") continue;  // a WebSocket upgrade: see stream_test.cpp
      std::string target = path;
      std::size_t at = 0;
      while ((at = target.find('{')) != std::string::npos) {
        target.replace(at, target.find('}', at) - at + 1, "999999");
      }
      ASSERT_EQ(target.find('{'), std::string::npos) << "unhandled path parameter in " << path;
      const std::string body = method == "post" || method == "put" ? "{}" : "";
      std::string upper = method;
      for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      const HttpReply reply = admin().request(upper, target, body);
      const std::string where = upper + " " + path;
      EXPECT_NE(reply.status, 405) << where << " is documented but not served";
      if (reply.status == 404) {
        EXPECT_NE(reply.error_code(), "not_found") << where << " is documented but not served";
      }
      EXPECT_TRUE(operation.at("responses").contains(std::to_string(reply.status)))
          << where << " answered " << reply.status << " (" << reply.body.substr(0, 120)
          << "), which its responses do not list";

      // Without a token: 401, and documented, unless the operation is public.
      const bool is_public = operation.contains("security") && operation.at("security").empty();
      const HttpReply anonymous_reply = anonymous().request(upper, target, body, "");
      if (is_public) {
        EXPECT_NE(anonymous_reply.status, 401) << where << " is documented as public";
      } else {
        EXPECT_EQ(anonymous_reply.status, 401) << where;
        EXPECT_TRUE(operation.at("responses").contains("401")) << where << " does not document 401";
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 28);
}

// Each operation's description names its role ("Role: `operator` or higher."): the role below it
// gets 403, the role itself does not.
TEST_F(OpenApiTest, DocumentedRolesAreEnforced) {
  const json doc = document();
  const std::map<std::string, int> rank = {{"viewer", 0}, {"operator", 1}, {"admin", 2}};
  const std::vector<HttpClient> clients = {viewer(), operator_client(), admin()};
  int checked = 0;
  for (const auto& [path, item] : doc.at("paths").items()) {
    if (path == "/api/v1/stream") continue;
    for (const auto& method : kMethods) {
      if (!item.contains(method)) continue;
      const std::string description = item.at(method).value("description", "");
      const auto at = description.find("Role: `");
      if (at == std::string::npos) continue;
      const std::string role = description.substr(at + 7, description.find('`', at + 7) - at - 7);
      ASSERT_TRUE(rank.count(role)) << path << ": " << role;
      std::string target = path;
      std::size_t id = 0;
      while ((id = target.find('{')) != std::string::npos) {
        target.replace(id, target.find('}', id) - id + 1, "999999");
      }
      std::string upper = method;
      for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      // An invalid body, so that an allowed call changes nothing.
      const std::string body = method == "post" || method == "put" ? "[]" : "";
      const int needed = rank.at(role);
      if (needed > 0) {
        const HttpReply below =
            clients[static_cast<std::size_t>(needed - 1)].request(upper, target, body);
        EXPECT_EQ(below.status, 403) << upper << " " << path << " is documented as " << role;
      }
      const HttpReply allowed =
          clients[static_cast<std::size_t>(needed)].request(upper, target, body);
      EXPECT_NE(allowed.status, 403) << upper << " " << path << " is documented as " << role;
      EXPECT_NE(allowed.status, 401) << upper << " " << path;
      ++checked;
    }
  }
  EXPECT_GE(checked, 25);
}

TEST_F(OpenApiTest, ErrorStatusesTheServerGivesAreDocumented) {
  const json doc = document();
  const std::string office =
      std::to_string(viewer().get("/api/v1/maps").json().at(0).at("id").get<int>());
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  const std::vector<StatusCase> cases = {
      {"POST", "/api/v1/teleop", R"({"v":0.1,"w":0})", operator_client(), 409},
      {"POST", "/api/v1/teleop", R"({"v":0.1,"w":0})", viewer(), 403},
      {"POST", "/api/v1/teleop", R"({"v":NaN,"w":0})", operator_client(), 400},
      {"POST", "/api/v1/estop", R"({"engaged":"no"})", operator_client(), 400},
      {"POST", "/api/v1/estop", R"({"engaged":true})", viewer(), 403},
      {"POST", "/api/v1/maps", R"({"name":"x"})", admin(), 400},
      {"POST", "/api/v1/maps", R"({"name":"x"})", operator_client(), 403},
      {"DELETE", "/api/v1/maps/" + office, "", admin(), 409},
      {"DELETE", "/api/v1/maps/" + office, "", operator_client(), 403},
      {"POST", "/api/v1/maps/" + office + "/activate", "", viewer(), 403},
      {"GET", "/api/v1/runs/1/trajectory?format=xml", "", viewer(), 400},
      {"POST", "/api/v1/sim/reset", R"({"world":"atlantis"})", operator_client(), 400},
      {"POST", "/api/v1/sim/reset", R"({"pose":{"x":0.05,"y":0.05}})", operator_client(), 400},
      {"POST", "/api/v1/sim/reset", "{}", viewer(), 403},
      {"PUT", "/api/v1/sim/clock", R"({"time_scale":1000})", operator_client(), 400},
      {"POST", "/api/v1/sim/obstacles", R"({"x":1,"y":1,"radius":0})", operator_client(), 400},
      {"POST", "/api/v1/tokens", R"({"role":"root"})", admin(), 400},
      {"GET", "/api/v1/tokens", "", operator_client(), 403},
  };
  expect_statuses_documented(doc, cases);
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
}

TEST_F(OpenApiTest, GoalAndLocalizationErrorStatusesAreDocumented) {
  const json doc = document();
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  const std::vector<StatusCase> cases = {
      {"POST", "/api/v1/goals", R"({"x":5,"y":7.5})", viewer(), 403},
      {"POST", "/api/v1/goals", R"({"x":NaN,"y":7.5})", operator_client(), 400},
      {"POST", "/api/v1/goals", R"({"x":5,"y":7.5,"planner":"rrt"})", operator_client(), 400},
      {"POST", "/api/v1/goals", R"({"x":5,"y":6.42})", operator_client(), 422},
      {"POST", "/api/v1/goals", R"({"x":50,"y":7.5})", operator_client(), 422},
      {"POST", "/api/v1/goals", R"({"x":5,"y":7.5,"controller":"potential_field"})",
       operator_client(), 422},
      {"GET", "/api/v1/goals/999999", "", viewer(), 404},
      {"DELETE", "/api/v1/goals/999999", "", operator_client(), 404},
      {"DELETE", "/api/v1/goals/999999", "", viewer(), 403},
      {"POST", "/api/v1/localization/pose", R"({"x":2,"y":7.5,"theta":0,"cov":[1]})",
       operator_client(), 400},
      {"POST", "/api/v1/localization/pose", R"({"x":2,"y":7.5,"theta":0})", viewer(), 403},
  };
  expect_statuses_documented(doc, cases);
  // Under e-stop a goal is a conflict; an accepted one is 201 and can be canceled once.
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  const HttpReply refused = operator_client().post("/api/v1/goals", json{{"x", 5.0}, {"y", 7.5}});
  EXPECT_EQ(refused.status, 409) << refused.body;
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  const json& goals = doc.at("paths").at("/api/v1/goals").at("post").at("responses");
  EXPECT_TRUE(goals.contains("409"));
  EXPECT_TRUE(goals.contains("201"));
  const HttpReply created = operator_client().post("/api/v1/goals", json{{"x", 5.0}, {"y", 7.5}});
  ASSERT_EQ(created.status, 201) << created.body;
  const std::string target = "/api/v1/goals/" + std::to_string(created.json().at("id").get<int>());
  EXPECT_EQ(operator_client().del(target).status, 200);
  EXPECT_EQ(operator_client().del(target).status, 409);
  EXPECT_TRUE(
      doc.at("paths").at("/api/v1/goals/{id}").at("delete").at("responses").contains("409"));
}

TEST_F(OpenApiTest, StreamDocumentsThePathAndGoalTopics) {
  const json doc = document();
  const std::string description = doc.at("paths").at("/api/v1/stream").at("get").at("description");
  EXPECT_NE(description.find("- `path`"), std::string::npos);
  EXPECT_NE(description.find("- `goal`"), std::string::npos);
  const json& topics =
      doc.at("components").at("schemas").at("StreamSubscribe").at("properties").at("topics");
  const json& names = topics.at("items").at("enum");
  for (const char* name : {"path", "goal"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), json(name)), names.end()) << name;
  }
}

// The topics a client may subscribe to are the ones the server's hello advertises, no more, no
// fewer: a topic added to the server must be added to the document.
TEST_F(OpenApiTest, StreamTopicsAreTheOnesTheServerOffers) {
  const json doc = document();
  const json& names = doc.at("components")
                          .at("schemas")
                          .at("StreamSubscribe")
                          .at("properties")
                          .at("topics")
                          .at("items")
                          .at("enum");
  std::set<std::string> documented;
  for (const auto& name : names) documented.insert(name.get<std::string>());
  WsClient stream(port(), viewer_token());
  std::set<std::string> offered;
  for (const auto& topic : stream.hello().at("topics")) offered.insert(topic.at("name"));
  EXPECT_EQ(documented, offered);
}

}  // namespace
}  // namespace mobot::testing

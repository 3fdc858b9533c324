// The dashboard's files (api/static_files.cpp): served from web_dir and from nowhere else.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "fake_ports.h"

namespace mobot::api {
namespace {

class StaticFilesTest : public ::testing::Test {
 protected:
  StaticFilesTest()
      : root_(std::filesystem::temp_directory_path() /
              ("mobot_static_test_" + std::to_string(::getpid()))),
        hub_(StreamOptions{}),
        rest_(robot_.ports(), hub_, {root_ / "web", "test"}) {
    std::filesystem::create_directories(root_ / "web" / "assets");
    std::ofstream(root_ / "web" / "index.html") << "<title>dashboard</title>";
    std::ofstream(root_ / "web" / "assets" / "app.js") << "app();";
    std::ofstream(root_ / "secret.txt") << "outside";
  }
  ~StaticFilesTest() override { std::filesystem::remove_all(root_); }

  Response get(const std::string& target) {
    std::optional<Response> reply;
    rest_.handle(Request{http::verb::get, target, 11},
                 [&](Response response) { reply = std::move(response); });
    EXPECT_TRUE(reply.has_value());
    return reply ? *reply : Response{};
  }

  std::filesystem::path root_;
  test::FakePorts robot_;
  StreamHub hub_;
  RestApi rest_;
};

TEST_F(StaticFilesTest, ServesTheDashboardsFiles) {
  EXPECT_EQ(get("/").body(), "<title>dashboard</title>");
  EXPECT_EQ(get("/index.html").body(), "<title>dashboard</title>");
  const Response asset = get("/assets/app.js");
  EXPECT_EQ(asset.result_int(), 200);
  EXPECT_EQ(asset.body(), "app();");
  EXPECT_NE(asset[http::field::cache_control].find("immutable"), std::string::npos);
}

TEST_F(StaticFilesTest, NothingOutsideWebDirIsServed) {
  const std::string secret = (root_ / "secret.txt").string();  // an absolute path
  const std::vector<std::string> targets{
      "/" + secret,         "/%2F" + secret.substr(1),  "//" + secret.substr(1), "/../secret.txt",
      "/%2e%2e/secret.txt", "/assets/../../secret.txt", "//etc/passwd"};
  for (const std::string& target : targets) {
    const Response response = get(target);
    EXPECT_EQ(response.result_int(), 404) << target;
    EXPECT_EQ(response.body().find("outside"), std::string::npos) << target;
  }
}

}  // namespace
}  // namespace mobot::api

// Maps: import (PGM, PNG), list, get, exports (PNG, ROS map_server PGM + YAML), activation (the
// map topic re-publishes), deletion, and every way an import can be wrong.
#include <sstream>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class MapsTest : public ServerSuite<MapsTest> {
 protected:
  void TearDown() override {
    // Leave the world's map active for the next test.
    admin().post("/api/v1/maps/" + std::to_string(office_id()) + "/activate", "");
    ServerSuite::TearDown();
  }

  static std::int64_t office_id() {
    for (const auto& map : viewer().get("/api/v1/maps").json()) {
      if (map.at("name") == "office") return map.at("id").get<std::int64_t>();
    }
    return -1;
  }

  static std::int64_t import_map(const std::string& name, const std::string& image) {
    const HttpReply reply = admin().post("/api/v1/maps", map_import_body(name, image));
    EXPECT_EQ(reply.status, 201) << reply.body;
    if (reply.status != 201) return -1;
    EXPECT_TRUE(reply.json().at("id").is_number_integer());
    return reply.json().at("id").get<std::int64_t>();
  }

  static std::size_t map_count() { return viewer().get("/api/v1/maps").json().size(); }
};

// A parsed binary PGM: width, height and pixels (top row first).
struct Pgm {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

Pgm parse_pgm(const std::string& bytes) {
  std::istringstream in(bytes);
  std::string magic;
  in >> magic;
  EXPECT_EQ(magic, "P5");
  auto next_number = [&in]() {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string comment;
      std::getline(in, comment);
      in >> std::ws;
    }
    int value = -1;
    in >> value;
    return value;
  };
  Pgm pgm;
  pgm.width = next_number();
  pgm.height = next_number();
  const int max_value = next_number();
  EXPECT_EQ(max_value, 255);
  in.get();  // the single whitespace before the pixels
  const auto offset = static_cast<std::size_t>(in.tellg());
  pgm.pixels.assign(bytes.begin() + static_cast<std::ptrdiff_t>(offset), bytes.end());
  return pgm;
}

TEST_F(MapsTest, TheWorldMapIsListedAndActive) {
  const HttpReply reply = viewer().get("/api/v1/maps");
  ASSERT_EQ(reply.status, 200);
  const json maps = reply.json();
  ASSERT_TRUE(maps.is_array());
  int active = 0;
  bool office = false;
  for (const auto& map : maps) {
    for (const char* key :
         {"id", "name", "width", "height", "resolution", "origin", "created", "active"}) {
      EXPECT_TRUE(map.contains(key)) << key << " in " << map.dump();
    }
    if (map.at("active").get<bool>()) ++active;
    if (map.at("name") == "office") {
      office = true;
      EXPECT_TRUE(map.at("active").get<bool>());
      EXPECT_EQ(map.at("width"), 400);
      EXPECT_EQ(map.at("height"), 300);
      EXPECT_DOUBLE_EQ(map.at("resolution").get<double>(), 0.05);
      EXPECT_DOUBLE_EQ(map.at("origin").at("x").get<double>(), 0.0);
      EXPECT_DOUBLE_EQ(map.at("origin").at("y").get<double>(), 0.0);
    }
  }
  EXPECT_TRUE(office);
  EXPECT_EQ(active, 1);
}

TEST_F(MapsTest, ImportPgmAndReadItBack) {
  const auto before = map_count();
  const std::int64_t id = import_map("pgm map", make_pgm(20, 10, test_map_pixels(20, 10)));
  ASSERT_GT(id, 0);
  EXPECT_EQ(map_count(), before + 1);

  const HttpReply reply = viewer().get("/api/v1/maps/" + std::to_string(id));
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json map = reply.json();
  EXPECT_EQ(map.at("id"), id);
  EXPECT_EQ(map.at("name"), "pgm map");
  EXPECT_EQ(map.at("width"), 20);
  EXPECT_EQ(map.at("height"), 10);
  EXPECT_DOUBLE_EQ(map.at("resolution").get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(map.at("origin").at("x").get<double>(), -1.0);
  EXPECT_DOUBLE_EQ(map.at("origin").at("y").get<double>(), -2.0);
  EXPECT_DOUBLE_EQ(map.at("origin").at("theta").get<double>(), 0.0);
  EXPECT_FALSE(map.at("active").get<bool>());
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  EXPECT_NEAR(map.at("created").get<double>(), now, 300.0);
}

TEST_F(MapsTest, ImportPngAndReadItBack) {
  const std::int64_t id = import_map("png map", make_png(30, 12, test_map_pixels(30, 12)));
  ASSERT_GT(id, 0);
  const json map = viewer().get("/api/v1/maps/" + std::to_string(id)).json();
  EXPECT_EQ(map.at("name"), "png map");
  EXPECT_EQ(map.at("width"), 30);
  EXPECT_EQ(map.at("height"), 12);
  // The cells survived: the exported PGM has the imported pixels.
  const Pgm pgm = parse_pgm(viewer().get("/api/v1/maps/" + std::to_string(id) + "/map.pgm").body);
  EXPECT_EQ(pgm.width, 30);
  EXPECT_EQ(pgm.height, 12);
  EXPECT_EQ(pgm.pixels, test_map_pixels(30, 12));
}

TEST_F(MapsTest, ExportsAreRosMapServerFiles) {
  const std::int64_t id = import_map("exported", make_pgm(20, 10, test_map_pixels(20, 10)));
  ASSERT_GT(id, 0);
  const std::string base = "/api/v1/maps/" + std::to_string(id);

  const HttpReply png = viewer().get(base + "/image");
  ASSERT_EQ(png.status, 200);
  EXPECT_EQ(png.header("content-type"), "image/png");
  ASSERT_GE(png.body.size(), 8U);
  EXPECT_EQ(png.body.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: width and height, big-endian, at offsets 16 and 20.
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png.body[at]) << 24) |
           (static_cast<unsigned char>(png.body[at + 1]) << 16) |
           (static_cast<unsigned char>(png.body[at + 2]) << 8) |
           static_cast<unsigned char>(png.body[at + 3]);
  };
  EXPECT_EQ(png.body.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(16), 20);
  EXPECT_EQ(be32(20), 10);

  const HttpReply pgm = viewer().get(base + "/map.pgm");
  ASSERT_EQ(pgm.status, 200);
  EXPECT_EQ(pgm.header("content-type"), "image/x-portable-graymap");
  EXPECT_NE(pgm.header("content-disposition").find("map.pgm"), std::string::npos);
  const Pgm parsed = parse_pgm(pgm.body);
  EXPECT_EQ(parsed.width, 20);
  EXPECT_EQ(parsed.height, 10);
  // map_saver's values: occupied 0, free 254, unknown 205, top row first, as imported.
  EXPECT_EQ(parsed.pixels, test_map_pixels(20, 10));

  const HttpReply yaml = viewer().get(base + "/map.yaml");
  ASSERT_EQ(yaml.status, 200);
  EXPECT_NE(yaml.header("content-type").find("yaml"), std::string::npos);
  EXPECT_NE(yaml.header("content-disposition").find("map.yaml"), std::string::npos);
  for (const char* line : {"image: map.pgm", "resolution: 0.1", "origin: [-1, -2, 0]", "negate: 0",
                           "occupied_thresh: 0.65", "free_thresh: 0.196"}) {
    EXPECT_NE(yaml.body.find(line), std::string::npos) << line << " in\n" << yaml.body;
  }
}

TEST_F(MapsTest, NegateAndThresholdsFollowMapServer) {
  json body = map_import_body("negated", make_pgm(20, 10, test_map_pixels(20, 10)));
  body["negate"] = true;
  HttpReply reply = admin().post("/api/v1/maps", body);
  ASSERT_EQ(reply.status, 201) << reply.body;
  Pgm pgm = parse_pgm(
      viewer()
          .get("/api/v1/maps/" + std::to_string(reply.json().at("id").get<int>()) + "/map.pgm")
          .body);
  ASSERT_EQ(pgm.pixels.size(), 200U);
  EXPECT_EQ(pgm.pixels[0], 254) << "a black border pixel is free when negated";
  EXPECT_EQ(pgm.pixels[10 * 20 - 1 - 20 - 1], 0) << "a white inside pixel is occupied when negated";

  // With free_thresh 0.1 and occupied_thresh 0.9 a mid grey (p = 0.5) is unknown, and with
  // 0.3 / 0.4 it is occupied.
  std::vector<std::uint8_t> grey(16, 128);
  body = map_import_body("wide thresholds", make_pgm(4, 4, grey));
  body["free_thresh"] = 0.1;
  body["occupied_thresh"] = 0.9;
  reply = admin().post("/api/v1/maps", body);
  ASSERT_EQ(reply.status, 201) << reply.body;
  pgm = parse_pgm(
      viewer()
          .get("/api/v1/maps/" + std::to_string(reply.json().at("id").get<int>()) + "/map.pgm")
          .body);
  EXPECT_EQ(pgm.pixels, std::vector<std::uint8_t>(16, 205));
  body["free_thresh"] = 0.3;
  body["occupied_thresh"] = 0.4;
  reply = admin().post("/api/v1/maps", body);
  ASSERT_EQ(reply.status, 201) << reply.body;
  pgm = parse_pgm(
      viewer()
          .get("/api/v1/maps/" + std::to_string(reply.json().at("id").get<int>()) + "/map.pgm")
          .body);
  EXPECT_EQ(pgm.pixels, std::vector<std::uint8_t>(16, 0));
}

TEST_F(MapsTest, InvalidImportsAre400AndStoreNothing) {
  const auto before = map_count();
  const json good = map_import_body("good", make_pgm(8, 8, test_map_pixels(8, 8)));
  auto with = [&good](const char* key, const json& value) {
    json body = good;
    body[key] = value;
    return body.dump();
  };
  auto without = [&good](const char* key) {
    json body = good;
    body.erase(key);
    return body.dump();
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {without("name"), "missing_field"},
      {without("resolution"), "missing_field"},
      {without("origin"), "missing_field"},
      {without("image_base64"), "missing_field"},
      {with("name", ""), "invalid_field"},
      {with("name", 42), "invalid_field"},
      {with("name", std::string(129, 'n')), "invalid_field"},
      {with("resolution", 0), "invalid_field"},
      {with("resolution", -0.05), "invalid_field"},
      {with("resolution", 11), "invalid_field"},
      {with("resolution", "0.05"), "invalid_field"},
      {with("origin", "0,0,0"), "invalid_field"},
      {with("origin", json::array({0, 0, 0})), "invalid_field"},
      {with("origin", json{{"x", 0}}), "missing_field"},
      {with("origin", json{{"x", "0"}, {"y", 0}}), "invalid_field"},
      {with("origin", json{{"x", 2e6}, {"y", 0}}), "invalid_field"},
      {with("origin", json{{"x", 0}, {"y", 0}, {"theta", 7}}), "invalid_field"},
      {with("negate", "yes"), "invalid_field"},
      {with("occupied_thresh", 1.5), "invalid_field"},
      {with("free_thresh", -0.1), "invalid_field"},
      {with("free_thresh", 0.7), "invalid_field"},  // above the default occupied_thresh
      {with("image_base64", ""), "invalid_field"},
      {with("image_base64", 12), "invalid_field"},
      {with("image_base64", "!!!!not base64!!!!"), "invalid_image"},
      {with("image_base64", "QUJD="), "invalid_image"},  // length not a multiple of 4
      {with("image_base64", base64_encode("this is not an image at all")), "invalid_image"},
      {with("image_base64", base64_encode("P5\n8 8\n255\n")), "invalid_image"},  // truncated PGM
      {with("image_base64", base64_encode(make_png(8, 8, test_map_pixels(8, 8)).substr(0, 40))),
       "invalid_image"},
      {R"({"name":"nan","resolution":NaN,"origin":{"x":0,"y":0},"image_base64":"AAAA"})",
       "malformed_json"},
      {"{\"name\":", "malformed_json"},
      {"[]", "invalid_body"},
  };
  for (const auto& [body, code] : cases) {
    const HttpReply reply = admin().post("/api/v1/maps", body);
    EXPECT_EQ(reply.status, 400) << body.substr(0, 160) << " -> " << reply.body;
    if (!code.empty()) {
      EXPECT_EQ(reply.error_code(), code) << body.substr(0, 160);
    }
  }
  EXPECT_EQ(map_count(), before) << "a refused import stored a map";
}

TEST_F(MapsTest, ImportsLargerThan64KiBAreAllowed) {
  // 300 x 300 = 90,000 pixels: the body is about 120 KB, above the general 64 KiB limit.
  const json body = map_import_body("large", make_pgm(300, 300, test_map_pixels(300, 300)), 0.05);
  ASSERT_GT(body.dump().size(), 64U * 1024U);
  const HttpReply reply = admin().post("/api/v1/maps", body);
  ASSERT_EQ(reply.status, 201) << reply.body.substr(0, 300);
  const json map =
      viewer().get("/api/v1/maps/" + std::to_string(reply.json().at("id").get<int>())).json();
  EXPECT_EQ(map.at("width"), 300);
  EXPECT_EQ(map.at("height"), 300);
}

TEST_F(MapsTest, ImportsLargerThan8MiBAre413) {
  const auto before = map_count();
  RawConnection connection(port());
  ASSERT_TRUE(connection.connected());
  // The limit is checked on the header: the body never has to be sent.
  connection.send("POST /api/v1/maps HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " +
                  server().token() + "\r\nContent-Type: application/json\r\nContent-Length: " +
                  std::to_string(8 * 1024 * 1024 + 1) + "\r\n\r\n");
  const auto reply = connection.read_http_reply(10s);
  ASSERT_TRUE(reply.has_value()) << "no answer to an oversized map import";
  EXPECT_EQ(reply->status, 413);
  EXPECT_EQ(reply->error_code(), "body_too_large");
  EXPECT_EQ(map_count(), before);
}

TEST_F(MapsTest, UnknownMapsAre404) {
  for (const std::string id : {"999999", "0", "-3", "abc", "1e3", "99999999999999999999"}) {
    const std::string base = "/api/v1/maps/" + id;
    for (const auto& reply : {admin().get(base), admin().get(base + "/image"),
                              admin().get(base + "/map.pgm"), admin().get(base + "/map.yaml"),
                              admin().post(base + "/activate", ""), admin().del(base)}) {
      EXPECT_EQ(reply.status, 404) << base << ": " << reply.body;
      EXPECT_EQ(reply.error_code(), "unknown_map") << base;
    }
  }
}

TEST_F(MapsTest, ActivateRepublishesTheMapOnTheStream) {
  WsClient json_client(port(), viewer_token());
  WsClient binary_client(port(), viewer_token());
  json_client.send({{"op", "subscribe"}, {"topics", {"map"}}, {"encoding", "json"}});
  binary_client.send({{"op", "subscribe"}, {"topics", {"map"}}});
  const auto initial = json_client.read_until("map", 10s);
  ASSERT_TRUE(initial.has_value()) << "no map on subscribe";
  EXPECT_EQ(initial->at("data").at("id"), office_id());
  const auto initial_binary = binary_client.read_binary(10s);
  ASSERT_TRUE(initial_binary.has_value());

  const std::int64_t id = import_map("activated", make_pgm(20, 10, test_map_pixels(20, 10)));
  ASSERT_GT(id, 0);
  const HttpReply reply =
      operator_client().post("/api/v1/maps/" + std::to_string(id) + "/activate", "");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.json().at("id"), id);
  EXPECT_TRUE(reply.json().at("active").get<bool>());
  for (const auto& map : viewer().get("/api/v1/maps").json()) {
    EXPECT_EQ(map.at("active").get<bool>(), map.at("id") == id) << map.dump();
  }

  const auto republished = json_client.read_until("map", 10s);
  ASSERT_TRUE(republished.has_value()) << "activation did not re-publish the map";
  const json& data = republished->at("data");
  EXPECT_EQ(data.at("id"), id);
  EXPECT_EQ(data.at("width"), 20);
  EXPECT_EQ(data.at("height"), 10);
  EXPECT_DOUBLE_EQ(data.at("resolution").get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(data.at("origin").at("x").get<double>(), -1.0);
  ASSERT_EQ(data.at("data").size(), 200U);
  // Row 0 is the bottom: cell (0,0) is the bottom-left border (occupied), the middle is free and
  // the top-left inside block (image rows 2..4, cols 2..9) is unknown.
  EXPECT_EQ(data.at("data").at(0), 100);
  EXPECT_EQ(data.at("data").at(2 * 20 + 12), 0);
  EXPECT_EQ(data.at("data").at(7 * 20 + 3), -1);
  EXPECT_GT(republished->at("seq").get<std::uint64_t>(), initial->at("seq").get<std::uint64_t>());

  const auto binary = binary_client.read_binary(10s);
  ASSERT_TRUE(binary.has_value());
  const BinaryHeader header = parse_binary_header(binary->payload);
  EXPECT_EQ(header.magic, "MBT1");
  EXPECT_EQ(header.topic_id, 2);
  const std::size_t body = header.header_bytes;
  EXPECT_EQ(read_le<std::uint32_t>(binary->payload, body), 20U);
  EXPECT_EQ(read_le<std::uint32_t>(binary->payload, body + 4), 10U);
  EXPECT_EQ(read_le<std::uint32_t>(binary->payload, body + 24), static_cast<std::uint32_t>(id));
  EXPECT_EQ(binary->payload.size(), body + 32 + 200);

  // Activating the world map again re-publishes it too.
  ASSERT_EQ(operator_client()
                .post("/api/v1/maps/" + std::to_string(office_id()) + "/activate", "")
                .status,
            200);
  const auto back = json_client.read_until("map", 10s);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->at("data").at("id"), office_id());
}

TEST_F(MapsTest, DeleteMaps) {
  const std::int64_t id = import_map("to delete", make_pgm(8, 8, test_map_pixels(8, 8)));
  ASSERT_GT(id, 0);
  const std::string target = "/api/v1/maps/" + std::to_string(id);
  const HttpReply deleted = admin().del(target);
  EXPECT_EQ(deleted.status, 204) << deleted.body;
  EXPECT_TRUE(deleted.body.empty());
  EXPECT_EQ(viewer().get(target).status, 404);
  EXPECT_EQ(viewer().get(target + "/map.pgm").status, 404);
  for (const auto& map : viewer().get("/api/v1/maps").json()) EXPECT_NE(map.at("id"), id);
  const HttpReply again = admin().del(target);
  EXPECT_EQ(again.status, 404);
  EXPECT_EQ(again.error_code(), "unknown_map");
}

TEST_F(MapsTest, TheActiveMapCannotBeDeleted) {
  const std::int64_t id = import_map("active one", make_pgm(8, 8, test_map_pixels(8, 8)));
  ASSERT_GT(id, 0);
  ASSERT_EQ(operator_client().post("/api/v1/maps/" + std::to_string(id) + "/activate", "").status,
            200);
  const HttpReply reply = admin().del("/api/v1/maps/" + std::to_string(id));
  EXPECT_EQ(reply.status, 409) << reply.body;
  EXPECT_EQ(reply.error_code(), "map_active");
  const HttpReply still = viewer().get("/api/v1/maps/" + std::to_string(id));
  ASSERT_EQ(still.status, 200);
  EXPECT_TRUE(still.json().at("active").get<bool>());

  // Once another map is active it can go.
  ASSERT_EQ(operator_client()
                .post("/api/v1/maps/" + std::to_string(office_id()) + "/activate", "")
                .status,
            200);
  EXPECT_EQ(admin().del("/api/v1/maps/" + std::to_string(id)).status, 204);
  const HttpReply office = admin().del("/api/v1/maps/" + std::to_string(office_id()));
  EXPECT_EQ(office.status, 409);
}

}  // namespace
}  // namespace mobot::testing

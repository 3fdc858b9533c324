#include <fstream>
#include <sstream>

#include "api/api_error.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

std::string_view content_type_of(const std::filesystem::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".html") return "text/html; charset=utf-8";
  if (extension == ".js" || extension == ".mjs") return "text/javascript; charset=utf-8";
  if (extension == ".css") return "text/css; charset=utf-8";
  if (extension == ".json" || extension == ".map") return "application/json";
  if (extension == ".svg") return "image/svg+xml";
  if (extension == ".png") return "image/png";
  if (extension == ".ico") return "image/x-icon";
  if (extension == ".woff2") return "font/woff2";
  return "application/octet-stream";
}

}  // namespace

Response RestApi::serve_static(const Request& request, std::string_view path) const {
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    throw ApiError(405, "method_not_allowed", "static files are read-only");
  }
  std::string relative = percent_decode(path);
  if (relative.empty() || relative == "/") relative = "/index.html";
  if (relative.find("..") != std::string::npos || relative.find('\0') != std::string::npos) {
    throw ApiError(404, "not_found", "no such file");
  }
  // Joined as a relative path: "//etc/passwd" (or "/%2Fetc/passwd") would otherwise be absolute,
  // and an absolute right-hand side makes path's operator/ drop web_dir altogether.
  const std::filesystem::path file =
      options_.web_dir / std::filesystem::path(relative).relative_path();
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    if (relative == "/index.html") {
      throw ApiError(404, "dashboard_not_built",
                     "the dashboard is not built: run `npm ci && npm run build` in web/ (" +
                         options_.web_dir.string() + ")");
    }
    throw ApiError(404, "not_found", "no such file");
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  Response response =
      bytes_response(request, http::status::ok, content_type_of(file), content.str());
  // Vite puts a content hash in asset names, so they may be cached; index.html may not.
  if (relative.starts_with("/assets/")) {
    response.set(http::field::cache_control, "public, max-age=31536000, immutable");
  }
  if (request.method() == http::verb::head) response.body().clear();
  return response;
}

}  // namespace mobot::api

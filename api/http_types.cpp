#include "api/http_types.h"

#include <cctype>
#include <cstdlib>

namespace mobot::api {

Response bytes_response(const Request& request, http::status status, std::string_view content_type,
                        std::string body) {
  Response response{status, request.version()};
  response.set(http::field::server, "mobotd");
  response.set(http::field::content_type, content_type);
  response.set(http::field::cache_control, "no-store");
  response.keep_alive(request.keep_alive());
  response.body() = std::move(body);
  response.prepare_payload();
  return response;
}

Response no_content_response(const Request& request) {
  Response response{http::status::no_content, request.version()};
  response.set(http::field::server, "mobotd");
  response.keep_alive(request.keep_alive());
  response.prepare_payload();
  return response;
}

Response json_response(const Request& request, http::status status, const nlohmann::json& body) {
  return bytes_response(request, status, "application/json",
                        body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

Response error_response(const Request& request, int status, const std::string& code,
                        const std::string& message) {
  return json_response(request, static_cast<http::status>(status),
                       {{"error", {{"code", code}, {"message", message}}}});
}

int http_status(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::kInvalid:
      return 400;
    case ErrorKind::kNotFound:
      return 404;
    case ErrorKind::kConflict:
      return 409;
    case ErrorKind::kImpossible:
      return 422;
  }
  return 500;
}

Response domain_error_response(const Request& request, const DomainError& error) {
  return error_response(request, http_status(error.kind), error.code, error.message);
}

std::string_view target_path(std::string_view target) {
  const auto query = target.find('?');
  return query == std::string_view::npos ? target : target.substr(0, query);
}

std::string percent_decode(std::string_view text) {
  std::string decoded;
  decoded.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size()) {
      const std::string hex(text.substr(i + 1, 2));
      char* end = nullptr;
      const long value = std::strtol(hex.c_str(), &end, 16);
      if (end == hex.c_str() + 2) {
        decoded.push_back(static_cast<char>(value));
        i += 2;
        continue;
      }
    }
    decoded.push_back(text[i] == '+' ? ' ' : text[i]);
  }
  return decoded;
}

std::string query_parameter(std::string_view target, std::string_view name) {
  const auto query_start = target.find('?');
  if (query_start == std::string_view::npos) return {};
  std::string_view query = target.substr(query_start + 1);
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (pair.substr(0, eq) == name) {
      return eq == std::string_view::npos ? std::string{} : percent_decode(pair.substr(eq + 1));
    }
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return {};
}

std::string redacted_target(std::string_view target) {
  const auto query_start = target.find('?');
  if (query_start == std::string_view::npos) return std::string(target);
  std::string out(target.substr(0, query_start + 1));
  std::string_view query = target.substr(query_start + 1);
  while (true) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    // The name as a client may have encoded it ("t%6Fken") counts too.
    if (percent_decode(pair.substr(0, eq)) == "token") {
      out.append(pair.substr(0, eq)).append("=REDACTED");
    } else {
      out.append(pair);
    }
    if (amp == std::string_view::npos) break;
    out.push_back('&');
    query.remove_prefix(amp + 1);
  }
  return out;
}

std::string bearer_token(const Request& request) {
  const auto header = request[http::field::authorization];
  constexpr std::string_view kPrefix = "bearer ";
  if (header.size() <= kPrefix.size()) return {};
  // RFC 7235: the scheme name is case-insensitive.
  for (std::size_t i = 0; i < kPrefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(header[i])) != kPrefix[i]) return {};
  }
  return std::string(header.substr(kPrefix.size()));
}

}  // namespace mobot::api

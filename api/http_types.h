#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include "api/ports/domain_error.h"

namespace mobot::api {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

// The largest request header the server reads (431 beyond it); the body's limit depends on the
// endpoint (RestApi::body_limit).
inline constexpr std::size_t kMaxRequestHeaderBytes = 16 * 1024;

Response json_response(const Request& request, http::status status, const nlohmann::json& body);
Response error_response(const Request& request, int status, const std::string& code,
                        const std::string& message);
Response bytes_response(const Request& request, http::status status, std::string_view content_type,
                        std::string body);
// The HTTP status of a refusal in the robot's terms: the one place the ports' ErrorKind meets HTTP.
int http_status(ErrorKind kind);
// A refusal from a port as `{"error":{"code","message"}}`, code and message as the port gave them.
Response domain_error_response(const Request& request, const DomainError& error);
// 204: done, nothing to say.
Response no_content_response(const Request& request);

// The target split into its path and the value of one query parameter (percent-decoded).
std::string_view target_path(std::string_view target);
std::string query_parameter(std::string_view target, std::string_view name);
// The token of an "Authorization: Bearer TOKEN" header (the scheme in any case), or "".
std::string bearer_token(const Request& request);
std::string percent_decode(std::string_view text);
// The target as it may be logged: the value of every `token` query parameter replaced by
// "REDACTED" (the stream's URL carries its token).
std::string redacted_target(std::string_view target);

}  // namespace mobot::api

#pragma once

#include <string_view>

namespace mobot::api {

// The OpenAPI 3 document of api/openapi.json, compiled into the binary so that an installed
// mobotd describes itself without its source tree.
std::string_view openapi_document();

}  // namespace mobot::api

#pragma once

#include <string>
#include <string_view>

#include "server/config.h"

namespace mobot::server {

// The config file's text to a Config, apart from the plugins' sections, which server/plugins
// reads (and with them most of the core: validate_config does both). Every key is checked for its
// type and range and misspelt keys are refused; the message of the ConfigError names the key and
// what it accepts (`source` names the file). No file is read here: the text may come from
// anywhere, a fuzzer included.
Config parse_config(std::string_view yaml_text, const std::string& source);
// The rules across keys (TLS's certificate and key both or neither, the backend, the laser rate within the control rate, the navigation
// speed within the limits, the mux's required sources); throws ConfigError.
void check_config_rules(const Config& config);

}  // namespace mobot::server

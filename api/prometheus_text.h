#pragma once

#include <string>
#include <string_view>

namespace mobot::api {

// Appends a metric's HELP and TYPE lines, for samples appended after them (append_sample).
void append_family(std::string& out, std::string_view name, std::string_view type,
                   std::string_view help);
// Appends one metric in the Prometheus text exposition format: its HELP and TYPE lines and the
// sample. `labels` is empty or the inside of the braces, e.g. sensor="laser".
void append_metric(std::string& out, std::string_view name, std::string_view type,
                   std::string_view help, double value, std::string_view labels = {});
// A further sample of a metric already introduced by append_metric (another label set).
void append_sample(std::string& out, std::string_view name, double value, std::string_view labels);
// `name="value"` with the value escaped as the format requires (backslash, quote, newline): for
// values that come from users (a token's label).
std::string label(std::string_view name, std::string_view value);
// A number as a label value (a histogram's `le`): shortest form, no trailing zeros.
std::string prometheus_number(double value);

}  // namespace mobot::api

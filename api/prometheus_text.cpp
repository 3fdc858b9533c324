#include "api/prometheus_text.h"

#include <cmath>
#include <cstdio>

namespace mobot::api {

void append_sample(std::string& out, std::string_view name, double value, std::string_view labels) {
  out.append(name);
  if (!labels.empty()) {
    out += '{';
    out.append(labels);
    out += '}';
  }
  char text[32];
  // Counters are integers: print them without a fraction, gauges with enough digits.
  if (value == std::floor(value) && std::abs(value) < 1e15) {
    std::snprintf(text, sizeof text, " %.0f\n", value);
  } else {
    std::snprintf(text, sizeof text, " %.9g\n", value);
  }
  out += text;
}

std::string label(std::string_view name, std::string_view value) {
  std::string out(name);
  out += "=\"";
  for (const char c : value) {
    if (c == '\\' || c == '"') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  out += '"';
  return out;
}

std::string prometheus_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void append_family(std::string& out, std::string_view name, std::string_view type,
                   std::string_view help) {
  out += "# HELP ";
  out.append(name);
  out += ' ';
  out.append(help);
  out += "\n# TYPE ";
  out.append(name);
  out += ' ';
  out.append(type);
  out += '\n';
}

void append_metric(std::string& out, std::string_view name, std::string_view type,
                   std::string_view help, double value, std::string_view labels) {
  append_family(out, name, type, help);
  append_sample(out, name, value, labels);
}

}  // namespace mobot::api

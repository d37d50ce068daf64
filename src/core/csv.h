#pragma once
/// CSV cells as RFC 4180 writes them: quoted (quotes doubled) when they hold a comma, a quote or
/// a line break. results.csv, compare's table and a campaign's jobs.csv share it.
#include <string>

namespace sscs {

inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace sscs

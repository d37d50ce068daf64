#include "report/report.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <unistd.h>

namespace sscs {

std::string subject_names(const Workcell& wc, const CheckResult& r, const char* separator) {
  std::string out;
  for (int s : r.subjects) {
    if (!out.empty()) out += separator;
    out += wc.objects[s].name;
  }
  return out;
}

std::string margin_text(const CheckResult& r) {
  if (!r.margin) return "";
  const char* unit = r.margin_unit();
  return fmt::format(" (margin {:g}{}{})", stable(*r.margin), *unit ? " " : "", unit);
}


}  // namespace sscs

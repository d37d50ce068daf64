#include "sweep/results.h"

#include <cmath>

#include <fmt/format.h>

#include "core/csv.h"
#include "report/json_writer.h"
#include <nlohmann/json.hpp>

#include "core/digest.h"
#include "core/units.h"

namespace sscs {

namespace {

using json = nlohmann::ordered_json;

std::string csv_number(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? fmt::format("{:.12g}", stable(*v)) : "";
}

/// Reads `path` as JSON and converts it with `convert`; nullopt with *error ("'path' is not
/// WHAT: ...") when the file is unreadable, not JSON, or lacks what `convert` asks for.
template <class Convert>
auto read_json_as(const std::string& path, std::string_view what, Convert convert) -> Expected<decltype(convert(json()))> {
  auto text = read_file_bytes(path);
  if (!text) return Unexpected{fmt::format("cannot read '{}'", path)};
  try {
    return convert(json::parse(*text));
  } catch (const json::exception& e) {
    return Unexpected{fmt::format("'{}' is not {}: {}", path, what, e.what())};
  }
}

json row_json(const VariantRow& row, const TableHeader& header) {
  json j;
  j["variant"] = row.index;
  j["folder"] = row.folder;
  json values = json::object();
  for (size_t i = 0; i < header.parameters.size() && i < row.values.size(); ++i) values[header.parameters[i].first] = row.values[i];
  j["values"] = values;
  j["status"] = row.status;
  j["passed"] = row.passed;
  j["failed"] = row.failed;
  j["warnings"] = row.warnings;
  json metrics = json::object();
  for (size_t i = 0; i < header.metrics.size() && i < row.metrics.size(); ++i) metrics[header.metrics[i]] = number_or_null(row.metrics[i]);
  j["metrics"] = metrics;
  if (header.simulated) {
    j["cycle_time"] = number_or_null(row.cycle_time);
    j["collisions"] = row.collisions ? json(*row.collisions) : json(nullptr);
  }
  j["message"] = row.message;
  return j;
}

}  // namespace

std::string result_json(const VariantRow& row, const TableHeader& header) { return row_json(row, header).dump(2) + "\n"; }

Expected<VariantRow> read_result(const std::string& path, const TableHeader& header) {
  return read_json_as(path, "a variant result of this sweep", [&](const json& j) {
    VariantRow row;
    row.index = j.at("variant").get<size_t>();
    row.folder = j.at("folder").get<std::string>();
    for (const auto& [name, unit] : header.parameters) row.values.push_back(j.at("values").at(name).get<std::string>());
    row.status = j.at("status").get<std::string>();
    row.passed = j.at("passed").get<size_t>();
    row.failed = j.at("failed").get<size_t>();
    row.warnings = j.at("warnings").get<size_t>();
    for (const std::string& m : header.metrics) {
      const json& v = j.at("metrics").at(m);
      row.metrics.push_back(v.is_null() ? std::nullopt : std::optional(v.get<double>()));
    }
    if (header.simulated) {
      if (!j.at("cycle_time").is_null()) row.cycle_time = j.at("cycle_time").get<double>();
      if (!j.at("collisions").is_null()) row.collisions = j.at("collisions").get<size_t>();
    }
    row.message = j.at("message").get<std::string>();
    return row;
  });
}

std::string manifest_json(const Manifest& m) {
  json j;
  j["sscs"] = 1;
  j["sweep"] = m.sweep;
  j["sweep_sha256"] = m.sweep_sha256;
  j["inputs_sha256"] = m.inputs_sha256;
  json inputs = json::array();
  for (const auto& [file, sha] : m.inputs) inputs.push_back({{"file", file}, {"sha256", sha}});
  j["inputs"] = std::move(inputs);
  j["variants"] = m.variants;
  j["mode"] = m.mode;
  j["version"] = m.version;
  if (!m.shard.empty()) j["shard"] = m.shard;
  return j.dump(2) + "\n";
}

Expected<Manifest> read_manifest(const std::string& path) {
  return read_json_as(path, "an sscs sweep manifest", [](const json& j) {
    Manifest m;
    m.sweep = j.at("sweep").get<std::string>();
    m.sweep_sha256 = j.at("sweep_sha256").get<std::string>();
    m.inputs_sha256 = j.at("inputs_sha256").get<std::string>();
    if (j.contains("inputs"))
      for (const json& i : j.at("inputs")) m.inputs.emplace_back(i.at("file").get<std::string>(), i.at("sha256").get<std::string>());
    m.variants = j.at("variants").get<size_t>();
    m.mode = j.at("mode").get<std::string>();
    m.version = j.at("version").get<std::string>();
    if (j.contains("shard")) m.shard = j.at("shard").get<std::string>();
    return m;
  });
}

std::string header_json(const TableHeader& h) {
  json j;
  j["sscs"] = 1;
  j["sweep"] = h.sweep;
  json params = json::array();
  for (const auto& [name, unit] : h.parameters) params.push_back({{"name", name}, {"unit", unit}});
  j["parameters"] = params;
  j["metrics"] = h.metrics;
  j["simulated"] = h.simulated;
  return j.dump();
}

std::string results_csv(const TableHeader& header, const std::vector<VariantRow>& rows) {
  std::vector<std::string> cols = {"variant", "folder"};
  for (const auto& [name, unit] : header.parameters) cols.push_back(name);
  for (const char* c : {"status", "passed", "failed", "warnings"}) cols.push_back(c);
  cols.insert(cols.end(), header.metrics.begin(), header.metrics.end());
  if (header.simulated) cols.insert(cols.end(), {"cycle_time", "collisions"});
  cols.push_back("message");
  std::string out;
  for (size_t i = 0; i < cols.size(); ++i) out += (i ? "," : "") + csv_field(cols[i]);
  out += "\n";
  for (const VariantRow& r : rows) {
    std::vector<std::string> f = {fmt::format("{}", r.index), r.folder};
    f.insert(f.end(), r.values.begin(), r.values.end());
    f.insert(f.end(), {r.status, fmt::format("{}", r.passed), fmt::format("{}", r.failed), fmt::format("{}", r.warnings)});
    for (const auto& m : r.metrics) f.push_back(csv_number(m));
    if (header.simulated) {
      f.push_back(csv_number(r.cycle_time));
      f.push_back(r.collisions ? fmt::format("{}", *r.collisions) : "");
    }
    f.push_back(r.message);
    for (size_t i = 0; i < f.size(); ++i) out += (i ? "," : "") + csv_field(f[i]);
    out += "\n";
  }
  return out;
}

std::string results_json(const TableHeader& header, const std::vector<VariantRow>& rows) {
  json j = json::parse(header_json(header));
  json list = json::array();
  for (const VariantRow& r : rows) list.push_back(row_json(r, header));
  j["variants"] = list;
  return j.dump(2) + "\n";
}

Expected<TableHeader> read_header(const std::string& path) {
  return read_json_as(path, "the results.json of an sscs sweep", [](const json& j) {
    TableHeader h;
    h.sweep = j.at("sweep").get<std::string>();
    for (const json& p : j.at("parameters")) h.parameters.emplace_back(p.at("name").get<std::string>(), p.at("unit").get<std::string>());
    h.metrics = j.at("metrics").get<std::vector<std::string>>();
    h.simulated = j.at("simulated").get<bool>();
    return h;
  });
}

}  // namespace sscs

#pragma once
/// HTML reports (`--html FILE` on check, simulate and sweep; `sscs report`): one self-contained
/// page, its scripts, styles, data and 3D model inlined, that opens from disk with no server and
/// no network (docs/reports.md). This stage assembles the page; what goes in it is gathered by
/// pipeline/html_report.h.
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace sscs {

/// The page's code, built into sscs (html_assets.cpp): scripts in load order, then the styles.
struct HtmlAssets {
  std::vector<std::string_view> scripts;
  std::string_view css;
};
HtmlAssets html_assets();

struct HtmlReport {
  std::string title;
  /// What the page shows: {"kind": "check" | "run" | "sweep", ...} (app.js reads it); models
  /// are named in it as "sscs-model-N", N indexing `models`.
  nlohmann::json data;
  std::vector<std::string> models;  ///< binary glTF files
};

/// `data` as the page's data element holds it: JSON in which no string can end the element.
std::string json_in_script(const nlohmann::json& data);

/// The page's bytes. Text inlined in <script> elements cannot end them: "</" is written "<\/".
std::string html_page(const HtmlReport& report);

/// `page` (html_page's) with one more inline script before its </body>, allowed by its hash, and
/// allowed to connect back to where the page came from (an EventSource): `sscs serve`'s pages.
/// `top`: HTML put first in the body, above the page's header (no script).
std::string with_live_script(const std::string& page, std::string_view script, std::string_view top = "");

}  // namespace sscs

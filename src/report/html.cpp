#include "report/html.h"

#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/digest.h"
#include "report/report.h"

namespace sscs {

namespace {

/// Code safe inside <script>: no "</" (it could close the element) and no "<!--".
std::string script_safe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    out.push_back(text[i]);
    if (text[i] == '<' && i + 1 < text.size() && (text[i + 1] == '/' || text[i + 1] == '!')) out.push_back('\\');
  }
  return out;
}

}  // namespace

/// JSON safe inside <script>, and still JSON: every `<`, `>` and `&` (only ever inside strings)
/// as its \u escape, so no string can close the element or open a comment (`<!` in a name
/// blanked the page: `<\!` is no JSON escape), and U+2028/2029 escaped too.
std::string json_in_script(const nlohmann::json& data) {
  const std::string text = data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '<') out += "\\u003c";
    else if (c == '>') out += "\\u003e";
    else if (c == '&') out += "\\u0026";
    else if (c == '\xe2' && i + 2 < text.size() && text[i + 1] == '\x80' && (text[i + 2] == '\xa8' || text[i + 2] == '\xa9')) {
      out += text[i + 2] == '\xa8' ? "\\u2028" : "\\u2029";
      i += 2;
    } else {
      out.push_back(c);
    }
  }
  return out;
}

/// The CSP source of one inline script: its SHA-256 in base64. Scripts are allowed by their
/// hashes alone, so an inline event handler (`onclick="..."`) never runs, whatever a string holds.
std::string script_hash(std::string_view script) {
  const std::string hex = sha256_hex(script);
  std::string raw;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) raw.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return fmt::format("'sha256-{}'", base64(raw));
}


std::string html_page(const HtmlReport& report) {
  const HtmlAssets assets = html_assets();
  std::string page;
  page += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  // Nothing may be fetched: the page's own inline scripts (by their hashes: no inline handler)
  // and styles, data: URLs for the model.
  std::vector<std::string> scripts;
  std::string hashes;
  for (std::string_view script : assets.scripts) {
    scripts.push_back("\n" + script_safe(script) + "\n");
    hashes += script_hash(scripts.back()) + " ";
  }
  page += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src " + hashes +
          "'unsafe-eval'; style-src 'unsafe-inline'; img-src data: blob:; connect-src data: blob:\">\n";
  page += fmt::format("<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n<div id=\"app\"></div>\n", xml_escape(report.title),
                      assets.css);
  page += "<script type=\"application/json\" id=\"sscs-data\">" + json_in_script(report.data) + "</script>\n";
  for (size_t i = 0; i < report.models.size(); ++i)
    page += fmt::format("<script type=\"application/octet-stream\" id=\"sscs-model-{}\">{}</script>\n", i, base64(report.models[i]));
  for (const std::string& script : scripts) page += "<script>" + script + "</script>\n";
  page += "</body>\n</html>\n";
  return page;
}

std::string with_live_script(const std::string& page, std::string_view script, std::string_view top) {
  std::string out = page;
  const std::string scripts = "script-src ", connect = "connect-src data: blob:";
  if (const size_t at = out.find(scripts); at != std::string::npos) out.insert(at + scripts.size(), script_hash(script) + " ");
  if (const size_t at = out.find(connect); at != std::string::npos) out.replace(at, connect.size(), "connect-src 'self' data: blob:");
  const size_t end = out.rfind("</body>");
  out.insert(end == std::string::npos ? out.size() : end, "<script>" + std::string(script) + "</script>\n");
  // What goes first: at the top of the page, above its header.
  const size_t body = out.find("<body>");
  out.insert(body == std::string::npos ? 0 : body + 6, std::string(top));
  return out;
}

}  // namespace sscs

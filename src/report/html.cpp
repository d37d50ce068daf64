#include "report/html.h"

#include <fmt/format.h>

#include "core/digest.h"
#include "report/report.h"

namespace sscs {

namespace {

/// Text safe inside <script>: no "</" (it could close the element) and no "<!--".
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

std::string html_page(const HtmlReport& report) {
  const HtmlAssets assets = html_assets();
  std::string page;
  page += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  // Nothing may be fetched: the page's own inline scripts and styles, data: URLs for the model.
  page += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'unsafe-inline' 'unsafe-eval'; "
          "style-src 'unsafe-inline'; img-src data: blob:; connect-src data: blob:\">\n";
  page += fmt::format("<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n<div id=\"app\"></div>\n", xml_escape(report.title),
                      assets.css);
  page += "<script type=\"application/json\" id=\"sscs-data\">" + script_safe(report.data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)) +
          "</script>\n";
  for (size_t i = 0; i < report.models.size(); ++i)
    page += fmt::format("<script type=\"application/octet-stream\" id=\"sscs-model-{}\">{}</script>\n", i, base64(report.models[i]));
  for (std::string_view script : assets.scripts) page += "<script>\n" + script_safe(script) + "\n</script>\n";
  page += "</body>\n</html>\n";
  return page;
}

}  // namespace sscs

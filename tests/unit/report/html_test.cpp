// The HTML page (report/html.h): one file, its scripts built in, nothing inlined able to end
// its <script> element, nothing fetched.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/html.h"

namespace sscs::testing {
namespace {

TEST(Html, AssetsAreBuiltInWholeAndSafeToInline) {
  const HtmlAssets assets = html_assets();
  ASSERT_EQ(assets.scripts.size(), 6u);  // three.js, its glTF loader and orbit controls, sscs's three
  EXPECT_GT(assets.scripts[0].size(), 500000u) << "three.min.js";
  EXPECT_NE(assets.scripts[0].find("REVISION=\"111\""), std::string_view::npos) << "three.js r111 (libjs-three)";
  EXPECT_NE(assets.scripts[1].find("THREE.GLTFLoader"), std::string_view::npos);
  EXPECT_NE(assets.scripts[2].find("THREE.OrbitControls"), std::string_view::npos);
  EXPECT_NE(assets.scripts[5].find("sscsReport"), std::string_view::npos) << "app.js last";
  EXPECT_NE(assets.css.find(".chip"), std::string_view::npos);
  for (std::string_view script : assets.scripts) {
    EXPECT_EQ(script.find("</"), std::string_view::npos);  // inlined as written
    EXPECT_EQ(script.find("<!--"), std::string_view::npos);
    EXPECT_EQ(script.back() == '\0', false);
  }
}

TEST(Html, DataCannotCloseItsScriptAndModelsAreInline) {
  HtmlReport report;
  report.title = "a <vault> & \"more\"";
  report.data = {{"kind", "check"}, {"message", "</script><script>alert(1)</script>"}, {"models", {"sscs-model-0"}}};
  report.models = {std::string("glTF\x02\0\0\0", 8)};
  const std::string page = html_page(report);
  EXPECT_NE(page.find("<title>a &lt;vault&gt; &amp; &quot;more&quot;</title>"), std::string::npos);
  EXPECT_EQ(page.find("</script><script>alert"), std::string::npos);
  EXPECT_NE(page.find("\\u003c/script\\u003e\\u003cscript\\u003ealert(1)\\u003c/script\\u003e"), std::string::npos);  // still the JSON string it was
  EXPECT_NE(page.find("<script type=\"application/octet-stream\" id=\"sscs-model-0\">Z2xURgIAAAA=</script>"), std::string::npos);
  // Nothing on the network: no src= or href= to fetch, and a policy that forbids it.
  EXPECT_EQ(page.find(" src="), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  EXPECT_NE(page.find("default-src 'none'"), std::string::npos);
}

/// The JSON the page carries, read back as the browser's JSON.parse would.
nlohmann::json page_data(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"sscs-data\">";
  const size_t from = page.find(open) + open.size();
  const size_t to = page.find("</script>", from);
  return nlohmann::json::parse(page.substr(from, to - from));
}

TEST(Html, AnyStringInTheDataComesBackAsItWasAndEndsNothing) {
  // Every string a vault, a run folder or a --set value may hold: HTML's comment and script
  // openers (a constraint named `the <!-- comment --> rule` blanked the page: `<\!` is no JSON
  // escape), the line separators JavaScript once took for line ends, bidi overrides, quotes.
  const std::vector<std::string> pieces = {"<!--", "<!", "-->", "</script", "</SCRIPT>", "<script>", "<", ">", "&", "\\",
                                           "\"", "'", "\xe2\x80\xa8", "\xe2\x80\xa9", "\xe2\x80\xae", "javascript:", "]]>", "\n", "x"};
  auto script_openers = [](const std::string& page) {
    size_t n = 0;
    for (size_t at = page.find("<script"); at != std::string::npos; at = page.find("<script", at + 1)) ++n;
    return n;
  };
  HtmlReport plain;
  plain.data = {{"kind", "check"}};
  const size_t openers = script_openers(html_page(plain));  // the page's own (three.js's text has one too)
  uint64_t state = 12345;
  auto next = [&state] { return (state = state * 6364136223846793005ULL + 1442695040888963407ULL) >> 33; };
  for (int trial = 0; trial < 300; ++trial) {
    std::string text;
    for (int k = 0, n = 1 + next() % 8; k < n; ++k) text += pieces[next() % pieces.size()];
    HtmlReport report;
    report.data = {{"kind", "check"}, {"name", text}, {text, {text, 1.5}}};
    const std::string page = html_page(report);
    ASSERT_EQ(page_data(page), report.data) << text;
    // Only the page's own script elements and comment-free data: one <script> opener per
    // element sscs writes, and no "<!--" anywhere.
    EXPECT_EQ(page.find("<!--"), std::string::npos) << text;
    EXPECT_EQ(script_openers(page), openers) << text;
  }
}

TEST(Html, ScriptsRunByTheirHashesSoNoInlineHandlerRuns) {
  HtmlReport report;
  report.data = {{"kind", "check"}};
  const std::string page = html_page(report);
  const size_t csp = page.find("script-src ");
  ASSERT_NE(csp, std::string::npos);
  const std::string policy = page.substr(csp, page.find(';', csp) - csp);
  EXPECT_EQ(policy.find("'unsafe-inline'"), std::string::npos) << policy;  // it would let onclick="..." run
  size_t hashes = 0;
  for (size_t at = policy.find("'sha256-"); at != std::string::npos; at = policy.find("'sha256-", at + 1)) ++hashes;
  EXPECT_EQ(hashes, html_assets().scripts.size());
}

}  // namespace
}  // namespace sscs::testing

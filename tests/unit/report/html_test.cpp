// The HTML page (report/html.h): one file, its scripts built in, nothing inlined able to end
// its <script> element, nothing fetched.
#include <gtest/gtest.h>

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
  EXPECT_NE(page.find("<\\/script><script>alert(1)<\\/script>"), std::string::npos);  // still the JSON string it was
  EXPECT_NE(page.find("<script type=\"application/octet-stream\" id=\"sscs-model-0\">Z2xURgIAAAA=</script>"), std::string::npos);
  // Nothing on the network: no src= or href= to fetch, and a policy that forbids it.
  EXPECT_EQ(page.find(" src="), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  EXPECT_NE(page.find("default-src 'none'"), std::string::npos);
}

}  // namespace
}  // namespace sscs::testing

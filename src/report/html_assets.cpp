// The HTML reports' scripts and styles, built into sscs so a report is one file that needs
// nothing at view time: three.js r111 and its glTF loader and orbit controls from Debian's
// libjs-three (SSCS_THREE_DIR), and sscs's own page (src/report/html/). The assembler includes
// each file's bytes (.incbin) followed by a NUL; CMake rebuilds this file when one changes.
#include "report/html.h"

#define SSCS_ASSET(symbol, file)                                                                   \
  __asm__(".pushsection .rodata\n.global " #symbol "\n.balign 16\n" #symbol ":\n.incbin \"" file \
          "\"\n.byte 0\n.global " #symbol "_end\n" #symbol "_end:\n.popsection\n")

SSCS_ASSET(sscs_asset_three, SSCS_THREE_DIR "/three.min.js");
SSCS_ASSET(sscs_asset_gltf_loader, SSCS_THREE_DIR "/examples/js/loaders/GLTFLoader.js");
SSCS_ASSET(sscs_asset_orbit_controls, SSCS_THREE_DIR "/examples/js/controls/OrbitControls.js");
SSCS_ASSET(sscs_asset_logic, SSCS_HTML_DIR "/logic.js");
SSCS_ASSET(sscs_asset_view3d, SSCS_HTML_DIR "/view3d.js");
SSCS_ASSET(sscs_asset_app, SSCS_HTML_DIR "/app.js");
SSCS_ASSET(sscs_asset_css, SSCS_HTML_DIR "/report.css");

extern "C" {
extern const char sscs_asset_three[], sscs_asset_three_end[];
extern const char sscs_asset_gltf_loader[], sscs_asset_gltf_loader_end[];
extern const char sscs_asset_orbit_controls[], sscs_asset_orbit_controls_end[];
extern const char sscs_asset_logic[], sscs_asset_logic_end[];
extern const char sscs_asset_view3d[], sscs_asset_view3d_end[];
extern const char sscs_asset_app[], sscs_asset_app_end[];
extern const char sscs_asset_css[], sscs_asset_css_end[];
}

namespace sscs {

namespace {
std::string_view span(const char* begin, const char* end) { return {begin, static_cast<size_t>(end - begin - 1)}; }  // less the NUL
}  // namespace

HtmlAssets html_assets() {
  return {{span(sscs_asset_three, sscs_asset_three_end), span(sscs_asset_gltf_loader, sscs_asset_gltf_loader_end),
           span(sscs_asset_orbit_controls, sscs_asset_orbit_controls_end), span(sscs_asset_logic, sscs_asset_logic_end),
           span(sscs_asset_view3d, sscs_asset_view3d_end), span(sscs_asset_app, sscs_asset_app_end)},
          span(sscs_asset_css, sscs_asset_css_end)};
}

}  // namespace sscs

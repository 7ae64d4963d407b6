// Files compiled into the binary at build time (cmake/assets.cmake), so that pictures and
// report pages need nothing beside the executable at run time.
#pragma once

#include <string_view>

namespace cmcsurf {

// DejaVu Sans (Debian fonts-dejavu-core), the TrueType font of the preview's text.
std::string_view font_ttf();

// The report page's script: web/src/page.js with three.js, bundled and minified by esbuild.
// Empty when the build had no npm (report_page_has_viewer() is false then).
std::string_view report_page_js();
bool report_page_has_viewer();

}  // namespace cmcsurf

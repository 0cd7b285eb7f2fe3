#pragma once
/// @file assets.hpp
/// The page's inline stylesheet and plotting script (assets.cpp).

namespace manta::report::detail {

/// CSS of the report page.
extern const char* const report_css;
/// JavaScript of the report page: x-y figure renderer with hover readout, the interactive 3-D
/// flight path, figure menus, SVG download, error capture and the rendered-plot count.
extern const char* const report_js;

}  // namespace manta::report::detail

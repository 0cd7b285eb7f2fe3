#pragma once
/// @file html.hpp
/// Text escaping for the self-contained HTML page and the JSON data embedded in it.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace manta::report {

/// Escape text for HTML element content and attribute values (& < > " ').
[[nodiscard]] std::string escape_html(std::string_view text);

/// JSON text safe inside `<script type="application/json">`: '<', '>' and '&' as \u003c, \u003e,
/// \u0026 (so "</script>" or "<!--" in a name cannot end the element), U+2028 and U+2029
/// escaped, invalid UTF-8 replaced by U+FFFD. JSON.parse gives back the original strings.
[[nodiscard]] std::string script_json(const nlohmann::json& j);

}  // namespace manta::report

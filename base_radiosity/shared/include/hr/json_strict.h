// Strict JSON for scene files: nlohmann's parser driven through a SAX handler of our own, which
// refuses duplicate keys (nlohmann would keep the last one silently; a scene that says "eps" twice is
// a mistake the user must see), bounds nesting, and turns every syntax error and overflowing number
// ("1e400") into an InputError naming the file and the line. Scene files and camera paths use it.
#pragma once
#include <nlohmann/json.hpp>

#include <string>

namespace hr {

/// Parses text (from file, for messages). Throws InputError.
nlohmann::json parseStrictJson(const std::string& text, const std::string& file);

}  // namespace hr

// Quoting user input in messages (see hr/echo.h).
#include <cstdio>
#include <hr/echo.h>
#include <hr/limits.h>

namespace hr {

std::string echo(std::string_view text) {
  std::string out = "\"";
  std::size_t n = 0;
  for (char ch : text) {
    if (n++ == limits::kMaxEcho) break;
    auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f || c == '"' || c == '\\') {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  out += "\"";
  if (text.size() > limits::kMaxEcho) {
    out.insert(out.size() - 1, "...");
    out += " (" + std::to_string(text.size()) + " bytes)";
  }
  return out;
}

std::string clipMessage(std::string_view message, std::size_t maxBytes) {
  if (message.size() <= maxBytes) return std::string(message);
  return std::string(message.substr(0, maxBytes)) + "... (message cut at " + std::to_string(maxBytes) + " of " +
         std::to_string(message.size()) + " bytes)";
}

}  // namespace hr

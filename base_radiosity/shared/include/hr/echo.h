// User input quoted in messages: at most limits::kMaxEcho characters, control bytes escaped, and the
// full length said when cut, so a 10 MB key or a binary token never floods the terminal.
#pragma once
#include <string>
#include <string_view>

namespace hr {

/// "\"text\"", or "\"first 64 characters...\" (10485760 bytes)" when longer.
std::string echo(std::string_view text);

/// A whole message cut to a sane length (the last line of defence in main()).
std::string clipMessage(std::string_view message, std::size_t maxBytes = 4096);

}  // namespace hr

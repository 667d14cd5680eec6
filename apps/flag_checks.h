// Command-line values checked against the limits table the scene readers use (hr/limits.h): a flag
// accepts exactly what the matching scene key accepts, and an unusable value is an error naming the
// flag (exit 2), never a silent fallback to a default. Flags that were not given stay empty.
#pragma once
#include <hr/limits.h>
#include <hr/types.h>

#include <optional>
#include <sstream>
#include <string>

template <class T>
void checkFlag(const char* flag, const std::optional<T>& v, const hr::limits::Range& r) {
  if (!v || hr::limits::within(static_cast<double>(*v), r)) return;
  std::ostringstream s;
  s << *v;
  throw hr::InputError(std::string(flag) + ": " + s.str() + " is outside the allowed range " + r.text() +
                       " (README \"Limits\")");
}

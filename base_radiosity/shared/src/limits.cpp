// Text of a limit for messages (see hr/limits.h).
#include <cstdio>
#include <hr/limits.h>

namespace hr::limits {

std::string Range::text() const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "[%.10g, %.10g]", lo, hi);
  return buf;
}

}  // namespace hr::limits

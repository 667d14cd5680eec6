// What an extension's save() hook writes, as one string: the tests compare and reload it whole (the
// solution file streams it instead).
#pragma once
#include <hr/extension.h>

#include <sstream>
#include <string>

namespace testutil {

inline std::string savedBytes(const hr::Extension& e) {
  std::ostringstream out;
  e.save(out);
  return std::move(out).str();
}

}  // namespace testutil

// The explicit table of extensions a host can load by name (--algorithm). No static-initializer
// registration: adding an extension means adding a row here.
#pragma once
#include <hr/extension.h>

#include <memory>
#include <string>
#include <vector>

namespace adapters {

struct ExtensionEntry {
  const char* name;
  const char* summary;
  std::unique_ptr<hr::Extension> (*make)();  // nullptr: the diffuse core alone
};

const std::vector<ExtensionEntry>& extensionTable();
/// Looks a name up; throws hr::InputError listing the valid names when it is unknown.
const ExtensionEntry& findExtension(const std::string& name);

}  // namespace adapters

// Extension options on the command line, and extensions loaded back from solutions.
#include "extension_cli.h"

#include "registry.h"
#include "vision/display_cells.h"

void ExtensionOptions::addTo(CLI::App* command) {
  // An option several extensions take (Radiance Clustering shares Illumination Samples' bases) is
  // added once, its help naming every one of them.
  for (const auto& entry : adapters::extensionTable()) {
    if (!entry.make) continue;
    for (const hr::OptionSpec& o : entry.make()->options()) {
      if (options_.count(o.name)) {
        std::string d = options_[o.name]->get_description();
        options_[o.name]->description(d.substr(0, d.size() - 1) + ", " + entry.name + ")");
        continue;
      }
      options_[o.name] = command->add_option("--" + o.name, values_[o.name],
                                             o.help + " (--algorithm " + entry.name + ")");
    }
  }
}

std::unique_ptr<hr::Extension> ExtensionOptions::make(const std::string& algorithm) const {
  const auto& entry = adapters::findExtension(algorithm);
  std::unique_ptr<hr::Extension> ext = entry.make ? entry.make() : nullptr;
  std::vector<hr::OptionValue> given;
  for (const auto& [name, opt] : options_) {
    if (opt->count() == 0) continue;
    bool accepted = false;
    if (ext)
      for (const hr::OptionSpec& o : ext->options()) accepted = accepted || o.name == name;
    if (!accepted)
      throw hr::InputError("--" + name + ": not an option of --algorithm " + algorithm);
    given.push_back({name, values_.at(name)});
  }
  if (ext) ext->configure(given);
  return ext;
}

std::unique_ptr<hr::Extension> loadExtension(const hr::Solution& s, const hr::HostView& view, const std::string& file) {
  if (s.extension.name.empty()) return nullptr;
  const adapters::ExtensionEntry* entry = nullptr;
  for (const auto& e : adapters::extensionTable())
    if (s.extension.name == e.name) entry = &e;
  if (!entry || !entry->make)
    throw hr::InputError(file + ": made with extension \"" + s.extension.name + "\", which this build does not have");
  auto ext = entry->make();
  // The VISION-like host's solutions address the extension's data by display cell (adapters/vision).
  if (s.host == "vision") ext = adapters::vision::adapt(std::move(ext));
  if (ext->formatVersion() != s.extension.version)
    throw hr::InputError(file + ": extension \"" + s.extension.name + "\" data version " +
                         std::to_string(s.extension.version) + " is not supported (expected " +
                         std::to_string(ext->formatVersion()) + "; solve the scene again with this build)");
  try {
    ext->load(s.extension.bytes, view);
  } catch (const hr::InputError& e) {
    throw hr::InputError(file + ": extension section: " + e.what());
  }
  return ext;
}

// The command line's side of the extension table: the options every registered extension accepts,
// collected on a subcommand; making and configuring the chosen extension (an option the chosen one
// does not take is refused, never ignored); and loading an extension's data back from a solution.
#pragma once
#include <CLI/CLI.hpp>
#include <hr/extension.h>
#include <hr/solution.h>

#include <map>
#include <memory>
#include <string>

class ExtensionOptions {
 public:
  /// Adds --NAME for every option of every extension in the table (each once).
  void addTo(CLI::App* command);
  /// The extension `algorithm` names (nullptr for "diffuse"), configured with the options given.
  /// Throws hr::InputError for an unknown name, an option it does not take or a bad value.
  std::unique_ptr<hr::Extension> make(const std::string& algorithm) const;

 private:
  std::map<std::string, std::string> values_;
  std::map<std::string, CLI::Option*> options_;
};

/// The solution's extension, made from the table by name and loaded with the solution's data over
/// `view` (which must outlive it); nullptr when the run had none. Throws hr::InputError when the
/// name is unknown or the data's version is not the extension's.
std::unique_ptr<hr::Extension> loadExtension(const hr::Solution& s, const hr::HostView& view, const std::string& file);

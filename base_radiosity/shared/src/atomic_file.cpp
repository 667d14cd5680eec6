// Atomic output: write to "<path>.tmp.<pid>", then rename over the target. A failed or interrupted
// run never leaves a half-written file under the real name.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <hr/output.h>

namespace hr {

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write(tmp);
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  writeAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error(path + ": cannot write file");
  });
}

}  // namespace hr

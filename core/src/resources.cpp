#include "forest/core/resources.hpp"

#include <cstdlib>
#include <string>

#include "forest/core/error.hpp"

namespace forest {
namespace fs = std::filesystem;

fs::path resourceDirectory(std::string_view kind) {
  if (kind != "shaders" && kind != "data") throw Error("resourceDirectory: unknown kind " + std::string(kind));
  const std::string variable = kind == "shaders" ? "FOREST_SHADER_DIR" : "FOREST_DATA_DIR";
  if (const char* env = std::getenv(variable.c_str()); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / FOREST_INSTALL_DATADIR / "forest" / kind;
    if (fs::is_directory(installed, ec)) return installed;
  }
  return fs::path(FOREST_SOURCE_DIR) / kind;
}

}  // namespace forest

#include "forest/core/files.hpp"

#include <fstream>
#include <sstream>
#include <system_error>
#include <unistd.h>

#include "forest/core/error.hpp"

namespace forest {
namespace fs = std::filesystem;

std::string readTextFile(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string() + ": no such file");
  if (fs::is_directory(file, ec)) throw InputError(file.string() + ": is a directory, expected a file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(systemErrorMessage(file.string() + ": cannot open"));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeAtomicallyWith(const fs::path& file, const std::function<void(const fs::path&)>& writer) {
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder.string() + ": cannot create folder: " + ec.message());
  static int counter = 0;
  const fs::path temporary = folder / ("." + file.stem().string() + ".tmp" + std::to_string(getpid()) +
                                       "-" + std::to_string(counter++) + file.extension().string());
  try {
    writer(temporary);
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  fs::rename(temporary, file, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw Error(file.string() + ": cannot replace with the new file: " + ec.message());
  }
}

void writeFileAtomic(const fs::path& file, std::string_view contents) {
  writeAtomicallyWith(file, [&](const fs::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(systemErrorMessage(temporary.string() + ": cannot open for writing"));
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw Error(systemErrorMessage(temporary.string() + ": write failed"));
  });
}

}  // namespace forest

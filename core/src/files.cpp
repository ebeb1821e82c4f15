#include "forest/core/files.hpp"

#include <fcntl.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>
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

namespace {

// The folder a path names, "." for a bare name.
fs::path folderOf(const fs::path& file) { return file.has_parent_path() ? file.parent_path() : fs::path("."); }

// Why no file can be created in the existing folder `folder` (empty: one was, and removed again).
std::string whyNoFileCanBeCreated(const fs::path& folder) {
  const fs::path probe = folder / (".forest-write-check-" + std::to_string(getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) return std::string("cannot create a file in it: ") + std::strerror(errno);
  ::close(fd);
  std::error_code ec;
  fs::remove(probe, ec);
  return {};
}

}  // namespace

std::string whyFolderIsNotWritable(const fs::path& folder) {
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec)) return "a file is there, expected a folder";
  // The folders the check creates, deepest first: removed again afterwards.
  std::vector<fs::path> created;
  for (fs::path f = folder; !f.empty() && !fs::exists(f, ec); f = f.parent_path()) created.push_back(f);
  for (const fs::path& f : created) {
    const fs::path parent = folderOf(f);
    if (fs::exists(parent, ec) && !fs::is_directory(parent, ec)) return "'" + parent.string() + "' is a file, not a folder";
  }
  std::string why;
  fs::create_directories(folder, ec);
  if (ec) why = "cannot create the folder: " + ec.message();
  else why = whyNoFileCanBeCreated(folder);
  for (const fs::path& f : created) fs::remove(f, ec);  // deepest first; each empty
  return why;
}

std::string whyFileIsNotWritable(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) return "a folder is there, expected a file";
  const fs::path folder = folderOf(file);
  if (!fs::exists(folder, ec)) return "its folder '" + folder.string() + "' does not exist";
  if (!fs::is_directory(folder, ec)) return "'" + folder.string() + "' is a file, not a folder";
  return whyNoFileCanBeCreated(folder);
}

}  // namespace forest

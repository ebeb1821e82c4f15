#pragma once
// File helpers. Every output file is written atomically: to a temporary file in the same folder,
// then renamed over the target, so an interrupted run never leaves a half-written file.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace forest {

// Whole file as text; throws InputError naming the file when it cannot be read.
std::string readTextFile(const std::filesystem::path& file);

// Writes `contents` to `file` atomically (creates missing parent folders).
void writeFileAtomic(const std::filesystem::path& file, std::string_view contents);

// Calls `writer` with a temporary path in the target's folder that keeps the target's extension
// (libraries that pick the format from the extension need it), then renames it to `file`.
// The temporary is removed if `writer` throws.
void writeAtomicallyWith(const std::filesystem::path& file,
                         const std::function<void(const std::filesystem::path& temporary)>& writer);

}  // namespace forest

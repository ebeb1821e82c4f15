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

// Why a run could not write its files into `folder` (its --out folder); empty when it can. Checked
// before any work by doing it: the folder and its missing parents are created and a file is
// created in it, and what the check created is removed again. The reason is one phrase, e.g.
// "a file is there, expected a folder" or "cannot create the folder: Permission denied".
std::string whyFolderIsNotWritable(const std::filesystem::path& folder);
// Why a run could not write `file` (an image, a JSON file); empty when it can: a folder is there,
// its folder does not exist (it is not created for it), or no file can be created in its folder.
std::string whyFileIsNotWritable(const std::filesystem::path& file);

}  // namespace forest

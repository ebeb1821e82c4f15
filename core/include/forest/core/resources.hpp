#pragma once
// Where the engine's read-only resources (shaders/, data/) are found at run time.
#include <filesystem>
#include <string_view>

namespace forest {

// `kind` is "shaders" or "data". Search order: $FOREST_SHADER_DIR / $FOREST_DATA_DIR;
// <exe>/../share/forest/<kind> (an installed build); the source tree's <kind>/ (a build tree).
std::filesystem::path resourceDirectory(std::string_view kind);

}  // namespace forest

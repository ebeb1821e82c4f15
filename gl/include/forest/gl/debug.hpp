#pragma once
// KHR_debug: driver messages go to the log; errors are also counted so tests can fail on them.
#include <cstdint>
#include <string>
#include <vector>

namespace forest::gl {

// Installs the debug callback on the current context (done by createContext when options.debug).
void enableDebugOutput();

// Messages of type GL_DEBUG_TYPE_ERROR (or high severity) seen since the last reset.
std::uint64_t debugErrorCount();
// Their texts (the most recent 64).
std::vector<std::string> debugErrorMessages();
void resetDebugErrors();

}  // namespace forest::gl

#pragma once
// The one place that includes the GL API (glad 2 loader, GL 4.5 core + KHR_debug).
#include <glad/gl.h>

#include <string>

namespace forest::gl {

// Throws forest::Error naming `what` if glGetError reports an error (drains all pending errors).
void checkError(const char* what);

}  // namespace forest::gl

// Shader errors are reported as file:line; a missing file names the file and the shader folder.
#include <gmock/gmock.h>

#include <filesystem>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/gl/shader.hpp"
#include "gl_test_support.hpp"

namespace forest::test {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

fs::path writeShader(const std::string& name, const std::string& text) {
  const fs::path file = fs::path(FOREST_TEST_OUTPUT) / ("shader-" + backendUnderTest()) / name;
  writeFileAtomic(file, text);
  return file;
}

TEST_F(GlTest, SyntaxErrorIsReportedAsFileAndLine) {
  const fs::path vert = writeShader("ok.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0); }\n");
  const fs::path frag = writeShader("bad.frag",
                                    "#version 450 core\n"
                                    "out vec4 color;\n"
                                    "void main() {\n"
                                    "  color = vec4(1.0) +;\n"  // line 4
                                    "}\n");
  const std::string e = errorOf([&] { gl::loadProgram({vert.string(), frag.string()}); });
  EXPECT_THAT(e, HasSubstr(frag.string() + ":4: "));
}

TEST_F(GlTest, DefinesKeepLineNumbers) {
  const fs::path vert = writeShader("ok2.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0); }\n");
  const fs::path frag = writeShader("bad2.frag",
                                    "#version 450 core\n"
                                    "out vec4 color;\n"
                                    "void main() { color = vec4(VALUE); }\n"
                                    "float broken = undefinedName;\n");  // line 4
  const std::string e = errorOf([&] { gl::loadProgram({vert.string(), frag.string()}, "#define VALUE 1.0\n"); });
  EXPECT_THAT(e, HasSubstr(frag.string() + ":4: "));
}

TEST_F(GlTest, MissingShaderFileIsNamed) {
  const std::string e = errorOf([] { gl::loadProgram({"does-not-exist.vert", "props.frag"}); });
  EXPECT_THAT(e, HasSubstr("does-not-exist.vert"));
  EXPECT_THAT(e, HasSubstr("no such file"));
  EXPECT_THAT(e, HasSubstr("FOREST_SHADER_DIR"));
}

TEST_F(GlTest, RepositoryShadersCompile) {
  EXPECT_NO_THROW(gl::loadProgram({"props.vert", "props.frag"}));
}

TEST(ShaderLog, DriverFormatsBecomeFileLine) {
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0:12(5): error: syntax error\n"), "a.frag:12: error: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0(7) : error C0000: syntax error"), "a.frag:7: error C0000: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "link failed"), "a.frag: link failed");
}

}  // namespace
}  // namespace forest::test

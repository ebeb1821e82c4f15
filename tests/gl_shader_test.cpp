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

// Locations come from a table read once at link (DESIGN §9: no glGetUniformLocation per draw); the
// table must give what the GL itself answers for every active uniform, an array by its name and by
// its first element, and -1 for names the linker removed or never saw.
TEST_F(GlTest, UniformLocationTableAgreesWithTheGl) {
  const gl::Program program = gl::compileProgram(
      {{GL_VERTEX_SHADER, "table.vert",
        "#version 450 core\nuniform mat4 uMatrix;\nuniform vec3 uOffsets[4];\nuniform float uUnused;\n"
        "void main() { gl_Position = uMatrix * vec4(uOffsets[gl_VertexID % 4], 1.0); }\n"},
       {GL_FRAGMENT_SHADER, "table.frag",
        "#version 450 core\nuniform vec4 uColour;\nuniform sampler2D uTexture;\nout vec4 colour;\n"
        "void main() { colour = uColour * texture(uTexture, vec2(0.5)); }\n"}});
  int checked = 0;
  for (const char* name : {"uMatrix", "uOffsets", "uOffsets[0]", "uColour", "uTexture", "uUnused", "uMissing"}) {
    EXPECT_EQ(program.location(name), glGetUniformLocation(program.id(), name)) << name;
    checked += glGetUniformLocation(program.id(), name) >= 0 ? 1 : 0;
  }
  EXPECT_EQ(checked, 5);  // all but the unused and the missing one are active
  EXPECT_EQ(program.location("uMissing"), -1);
}

TEST(ShaderLog, DriverFormatsBecomeFileLine) {
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0:12(5): error: syntax error\n"), "a.frag:12: error: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0(7) : error C0000: syntax error"), "a.frag:7: error C0000: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "link failed"), "a.frag: link failed");
}

}  // namespace
}  // namespace forest::test

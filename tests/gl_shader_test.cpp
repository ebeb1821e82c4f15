// Shader errors are reported as file:line; a missing file names the file and the shader folder.
#include <gmock/gmock.h>

#include <cstddef>
#include <filesystem>
#include <map>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/draw_view.hpp"
#include "forest/render/uniform_blocks.hpp"
#include "gl_test_support.hpp"
#include "test_paths.hpp"

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

// The uniform blocks (DESIGN §9) as the GL compiler lays them out must be the C++ structs that
// fill them (render/uniform_blocks.hpp): the same size, binding and member offsets, in every
// repository program that declares them — a member added on one side only, a vec3 where std140
// pads, or a wrong binding fails here instead of shading with shifted values.
struct BlockLayout {
  const char* block;
  GLuint binding;
  std::size_t bytes;
  std::vector<std::pair<const char*, std::size_t>> members;  // name in the block, offsetof
};

std::vector<BlockLayout> expectedBlocks() {
  using render::FrameBlock, render::TerrainViewBlock, render::ViewBlock;
  return {
      {"ViewBlock", render::kViewBlockBinding, sizeof(ViewBlock),
       {{"viewProjectionRelative", offsetof(ViewBlock, viewProjectionRelative)},
        {"lightDepthRow", offsetof(ViewBlock, lightDepthRow)},
        {"toSunAmbient", offsetof(ViewBlock, toSunAmbient)},
        {"sunColorSlopeBias", offsetof(ViewBlock, sunColorSlopeBias)},
        {"viewer", offsetof(ViewBlock, viewer)}}},
      {"TerrainViewBlock", render::kTerrainViewBlockBinding, sizeof(TerrainViewBlock),
       {{"originRelative", offsetof(TerrainViewBlock, originRelative)},
        {"eye", offsetof(TerrainViewBlock, eye)},
        {"lodEyeRelative", offsetof(TerrainViewBlock, lodEyeRelative)},
        {"morph[0]", offsetof(TerrainViewBlock, morph)}}},
      {"FrameBlock", render::kFrameBlockBinding, sizeof(FrameBlock),
       {{"eyeRelativeToShadow", offsetof(FrameBlock, eyeRelativeToShadow)},
        {"eyeRelativeLightDepth", offsetof(FrameBlock, eyeRelativeLightDepth)},
        {"rays[0]", offsetof(FrameBlock, rays)},
        {"toSunUp", offsetof(FrameBlock, toSunUp)},
        {"sunColorAmbient", offsetof(FrameBlock, sunColorAmbient)},
        {"skyFog", offsetof(FrameBlock, skyFog)},
        {"blur", offsetof(FrameBlock, blur)},
        {"modes", offsetof(FrameBlock, modes)},
        {"halfTerm", offsetof(FrameBlock, halfTerm)}}},
      {"ImpostorBlock", render::kImpostorBlockBinding, sizeof(render::ImpostorBlock),
       {{"grid", offsetof(render::ImpostorBlock, grid)},
        {"sphere[0]", offsetof(render::ImpostorBlock, sphere)},
        {"boxMin[0]", offsetof(render::ImpostorBlock, boxMin)},
        {"boxMax[0]", offsetof(render::ImpostorBlock, boxMax)},
        {"querySlabs[0]", offsetof(render::ImpostorBlock, querySlabs)},
        {"casterSlabs[0]", offsetof(render::ImpostorBlock, casterSlabs)}}},
      // QueryBatches::QueryView (culling/src/query_batches.hpp): a mat4, then the frame's stamp in a uvec4.
      {"QueryViewBlock", 3, sizeof(glm::mat4) + sizeof(glm::uvec4), {{"viewProjectionRelative", 0}, {"frameStamp", sizeof(glm::mat4)}}},
  };
}

GLint resourceProperty(GLuint program, GLenum interface, GLuint index, GLenum property) {
  GLint value = -1;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
  return value;
}

TEST_F(GlTest, UniformBlocksMatchTheShaders) {
  const std::string frameBlock = gl::readShader("frame_block.glsl");
  const std::string levels = "#define TERRAIN_LEVELS " + std::to_string(terrain::kLevels) + "\n";
  std::vector<std::pair<std::string, gl::Program>> programs;
  for (auto output : {render::SurfaceOutput::Lit, render::SurfaceOutput::GBuffer, render::SurfaceOutput::ObjectId,
                      render::SurfaceOutput::LightDepth}) {
    const std::string tag = std::to_string(static_cast<int>(output));
    programs.emplace_back("trees/" + tag, render::loadSurfaceProgram("trees.vert", "trees.frag", output));
    programs.emplace_back("props/" + tag, render::loadSurfaceProgram("props.vert", "props.frag", output));
    programs.emplace_back("terrain/" + tag, render::loadSurfaceProgram("terrain.vert", "terrain.frag", output, levels));
    programs.emplace_back("impostors/" + tag, render::loadSurfaceProgram("impostor.vert", "impostor.frag+crown_slab.glsl+cross_fade.glsl",
                                                                         output, gl::readShader("impostor.glsl")));
  }
  const std::string lookup = "#define PCF_RADIUS 1\n#define SHADOW_SLICES 4\n";  // the lookup's constants (ShadowLookupPrograms)
  // The half-resolution term and the lighting beyond its depth (AT_HALF_TERM_DEPTH) read halfTerm.
  programs.emplace_back("shadow term, half resolution",
                        gl::loadProgram({"fullscreen.vert", "shadow_term.frag", "shadow_lookup.frag", "gbuffer_read.frag"},
                                        "#define TERM_SCALE 2\n" + lookup + frameBlock));
  programs.emplace_back("blur", gl::loadProgram({"fullscreen.vert", "shadow_blur.frag", "blur_taps.frag"},
                                                "#define BLUR_TAPS 2\n#define BLUR_VERTICAL\n#define AT_HALF_TERM_REACH\n" + frameBlock));
  programs.emplace_back("lighting, blurred term",
                        gl::loadProgram({"fullscreen.vert", "lighting.frag", "sky_radiance.frag", "display_gamma.frag", "blur_taps.frag", "gbuffer_read.frag"},
                                        "#define BLURRED_TERM\n#define BLUR_TAPS 3\n#define HAZE\n" + frameBlock));
  programs.emplace_back("lighting, term upsampled",
                        gl::loadProgram({"fullscreen.vert", "lighting.frag", "sky_radiance.frag", "display_gamma.frag", "term_upsample.frag", "gbuffer_read.frag"},
                                        "#define UPSAMPLED_TERM\n#define AT_HALF_TERM_DEPTH\n" + frameBlock));
  programs.emplace_back("lighting, term looked up",
                        gl::loadProgram({"fullscreen.vert", "lighting.frag", "sky_radiance.frag", "display_gamma.frag", "shadow_lookup.frag", "gbuffer_read.frag"},
                                        "#define AT_HALF_TERM_DEPTH\n#define WITH_SKY\n" + lookup + frameBlock));
  programs.emplace_back("sky", gl::loadProgram({"fullscreen.vert", "sky.frag", "sky_radiance.frag", "display_gamma.frag"}, frameBlock));
  programs.emplace_back("query box", gl::loadProgram({"query_box.vert", "query_box.frag"}, gl::readShader("query_block.glsl")));

  std::map<std::string, int> programsWith;
  for (const auto& [name, program] : programs) {
    for (const BlockLayout& expected : expectedBlocks()) {
      const GLuint block = glGetProgramResourceIndex(program.id(), GL_UNIFORM_BLOCK, expected.block);
      if (block == GL_INVALID_INDEX) continue;
      ++programsWith[expected.block];
      SCOPED_TRACE(name + ": " + expected.block);
      EXPECT_EQ(resourceProperty(program.id(), GL_UNIFORM_BLOCK, block, GL_BUFFER_DATA_SIZE), static_cast<GLint>(expected.bytes));
      EXPECT_EQ(resourceProperty(program.id(), GL_UNIFORM_BLOCK, block, GL_BUFFER_BINDING), static_cast<GLint>(expected.binding));
      for (const auto& [member, offset] : expected.members) {
        const std::string full = std::string(expected.block) + "." + member;
        const GLuint index = glGetProgramResourceIndex(program.id(), GL_UNIFORM, full.c_str());
        ASSERT_NE(index, GL_INVALID_INDEX) << full;
        EXPECT_EQ(resourceProperty(program.id(), GL_UNIFORM, index, GL_OFFSET), static_cast<GLint>(offset)) << full;
      }
    }
  }
  // Every surface program reads the view block, the impostors theirs, the terrain's its own, the full-screen passes (the
  // term, the blur, three lighting programs, the sky) the frame block, the query boxes theirs.
  EXPECT_EQ(programsWith["ViewBlock"], 16);
  EXPECT_EQ(programsWith["ImpostorBlock"], 4);
  EXPECT_EQ(programsWith["TerrainViewBlock"], 4);
  EXPECT_EQ(programsWith["FrameBlock"], 6);
  EXPECT_EQ(programsWith["QueryViewBlock"], 1);
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

// shaders/display_gamma.frag against the closed form x^(1/2.2) over [0, 1] (4096 inputs, the ends
// included, and their squares for the dark end), evaluated on the GL: within the fit's stated
// bound, 0.12 / 255, plus float32 rounding.
TEST_F(GlTest, DisplayGammaIsWithinAQuarterStepOfPow) {
  constexpr int kInputs = 4096;
  const gl::Program program = gl::compileProgram(
      {{GL_VERTEX_SHADER, "ramp.vert",
        "#version 450 core\nvoid main() { gl_Position = vec4(2.0 * vec2(gl_VertexID & 1, gl_VertexID >> 1) * 2.0 - 1.0, 0.0, 1.0); }\n"},
       {GL_FRAGMENT_SHADER, "ramp.frag",
        "#version 450 core\nvec3 displayFromLinear(vec3 linear);\nout vec4 encoded;\n"
        "void main() { float x = floor(gl_FragCoord.x) / 4095.0; encoded = vec4(displayFromLinear(vec3(x, x * x, 0.0)), x); }\n"},
       {GL_FRAGMENT_SHADER, "display_gamma.frag", gl::readShader("display_gamma.frag")}});
  gl::Texture target(GL_RGBA32F, kInputs, 1);
  gl::Framebuffer framebuffer;
  framebuffer.attach(GL_COLOR_ATTACHMENT0, target);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
  glViewport(0, 0, kInputs, 1);
  glDisable(GL_DEPTH_TEST);
  gl::VertexArray empty;
  glBindVertexArray(empty.id());
  program.use();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  std::vector<float> texels(4 * kInputs);
  glGetTextureImage(target.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(texels.size() * 4), texels.data());
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  double worst = 0.0;
  for (int i = 0; i < kInputs; ++i) {
    const float x = texels[4 * static_cast<size_t>(i) + 3];  // the input the shader used, i / 4095
    ASSERT_NEAR(x, i / 4095.0, 1e-6) << i;
    for (int c = 0; c < 3; ++c) {
      const double linear = c == 0 ? x : c == 1 ? x * x : 0.0f;
      worst = std::max(worst, std::abs(texels[4 * static_cast<size_t>(i) + c] - std::pow(linear, 1.0 / 2.2)));
    }
  }
  EXPECT_LE(worst * 255.0, 0.12 + 255.0 * 1e-6);
  EXPECT_EQ(gl::debugErrorCount(), 0u);
}

TEST(ShaderLog, DriverFormatsBecomeFileLine) {
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0:12(5): error: syntax error\n"), "a.frag:12: error: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "0(7) : error C0000: syntax error"), "a.frag:7: error C0000: syntax error");
  EXPECT_EQ(gl::formatShaderLog("a.frag", "link failed"), "a.frag: link failed");
}

}  // namespace
}  // namespace forest::test

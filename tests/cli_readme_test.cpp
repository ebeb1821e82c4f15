// The README's sample outputs and docs/report-format.md stay true: every command the README shows
// with its output ("$ ./build/release/apps/forest …" in a code block) is run here in a short
// variant (fewer frames, a smaller image, fewer random cases), and every line of the sample must
// have the shape of a line the program prints now (the same words and punctuation, any numbers).
// The fields docs/report-format.md documents for report.json and the render record must exist in
// what the commands write.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "forest/core/files.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {

namespace fs = std::filesystem;

const fs::path kRepository = fs::path(FOREST_REPO_DATA).parent_path();

struct Sample {
  std::vector<std::string> arguments;  // after the program
  std::vector<std::string> output;     // the lines shown under the command
};

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// "$ ./build/release/apps/forest ARGS [\ continued]" inside ``` blocks, with the lines under it.
std::vector<Sample> readmeSamples() {
  const std::vector<std::string> readme = lines(readTextFile(kRepository / "README.md"));
  std::vector<Sample> samples;
  const std::string prompt = "$ ./build/release/apps/forest";
  for (size_t i = 0; i < readme.size(); ++i) {
    if (readme[i].rfind(prompt, 0) != 0) continue;
    std::string command = readme[i].substr(prompt.size());
    while (!command.empty() && command.back() == '\\' && i + 1 < readme.size()) command = command.substr(0, command.size() - 1) + readme[++i];
    Sample s;
    std::istringstream words(command);
    for (std::string w; words >> w;) s.arguments.push_back(w);
    for (++i; i < readme.size() && readme[i].rfind("```", 0) != 0; ++i)
      if (!readme[i].empty()) s.output.push_back(readme[i]);
    samples.push_back(s);
  }
  return samples;
}

// A line with its numbers as '#' and its runs of blanks as one space: what must stay the same.
std::string shape(const std::string& line) {
  static const std::regex number(R"([-+]?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?)"), blanks(R"(\s+)");
  std::string s = std::regex_replace(std::regex_replace(line, number, "#"), blanks, " ");
  const size_t first = s.find_first_not_of(' '), last = s.find_last_not_of(' ');
  return first == std::string::npos ? "" : s.substr(first, last - first + 1);
}

// The short variant: values of these flags replaced (or added, for commands that take them).
std::vector<std::string> shortened(std::vector<std::string> arguments, const fs::path& out) {
  const std::string command = arguments.front();
  std::map<std::string, std::string> values;
  if (command == "walkthrough" || command == "budget")
    values = {{"--frames", "6"}, {"--width", "160"}, {"--height", "120"}, {"--warmup", "2"}, {"--out", out.string()}};
  if (command == "stability") values = {{"--random", "300"}};
  if (command == "render") values = {{"--width", "160"}, {"--height", "90"}, {"--out", (out / "frame.png").string()}};
  for (size_t i = 1; i + 1 < arguments.size(); ++i)
    if (auto it = values.find(arguments[i]); it != values.end()) {
      arguments[i + 1] = it->second;
      values.erase(it);
    }
  for (const auto& [flag, value] : values) arguments.insert(arguments.end(), {flag, value});
  return arguments;
}

// Runs the program from the repository's root, as the README does.
test::CliResult runFromRepository(const std::vector<std::string>& arguments) {
  std::string joined;
  for (const std::string& a : arguments) joined += " " + a;
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / "cli";
  fs::create_directories(folder);
  const fs::path out = folder / "readme-stdout.txt", err = folder / "readme-stderr.txt";
  const std::string command = "cd '" + kRepository.string() + "' && " + FOREST_EXE + joined + " > " + out.string() + " 2> " +
                              err.string() + " < /dev/null";
  const int status = std::system(command.c_str());
  test::CliResult r;
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readTextFile(out);
  r.err = readTextFile(err);
  return r;
}

TEST(ForestReadme, EverySampleOutputHasTheShapeOfWhatTheCommandPrintsNow) {
  const std::vector<Sample> samples = readmeSamples();
  // info, the main job, the thesis demo, stability: a README with fewer samples lost them.
  ASSERT_GE(samples.size(), 4u);
  int index = 0;
  for (const Sample& sample : samples) {
    const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / ("readme-" + std::to_string(index++));
    fs::create_directories(out);  // render's --out names a file in it, whose folder must exist
    const std::vector<std::string> arguments = shortened(sample.arguments, out);
    std::string shown;
    for (const std::string& a : arguments) shown += " " + a;
    SCOPED_TRACE("forest" + shown);
    ASSERT_FALSE(sample.output.empty());
    const test::CliResult r = runFromRepository(arguments);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::vector<std::string> printed;
    for (const std::string& line : lines(r.out)) printed.push_back(shape(line));
    // What `info` prints depends on the machine's GL: only its labels ("backend:") must be there.
    const bool labelsOnly = sample.arguments.front() == "info";
    // The sample's output folder (the default, out/walkthrough; render's frame.png in the current
    // folder) is the test's folder here.
    const std::string testFolder = fs::proximate(out, kRepository).string();
    const bool render = sample.arguments.front() == "render";
    const std::string given = render ? "frame." : "out/walkthrough", replacement = render ? testFolder + "/frame." : testFolder;
    for (std::string line : sample.output) {
      for (size_t at = line.find(given); at != std::string::npos; at = line.find(given, at + replacement.size()))
        line.replace(at, given.size(), replacement);
      const std::string expected = labelsOnly ? line.substr(0, line.find(':') + 1) : shape(line);
      const bool found = std::any_of(printed.begin(), printed.end(),
                                     [&](const std::string& p) { return labelsOnly ? p.rfind(expected, 0) == 0 : p == expected; });
      EXPECT_TRUE(found) << "README line not printed now:\n  " << line << "\nshape: " << expected << "\nprinted:\n" << r.out;
    }
  }
}

// Field names of a docs/report-format.md table: the backticked names in the first column of the
// rows under `heading` up to the next blank line after the table ("frames[]" → "frames",
// "triangles.geometry" → a nested path).
std::vector<std::string> documentedFields(const std::string& heading) {
  const std::vector<std::string> doc = lines(readTextFile(kRepository / "docs" / "report-format.md"));
  std::vector<std::string> fields;
  auto at = std::find(doc.begin(), doc.end(), heading);
  EXPECT_NE(at, doc.end()) << heading;
  if (at == doc.end()) return fields;
  bool inTable = false;
  for (++at; at != doc.end(); ++at) {
    if (at->rfind("|", 0) != 0) {
      if (inTable) break;
      continue;
    }
    inTable = true;
    const std::string cell = at->substr(1, at->find('|', 1) - 1);
    static const std::regex name(R"(`([a-z0-9_.]+)(\[\])?`)");
    for (std::sregex_iterator m(cell.begin(), cell.end(), name), end; m != end; ++m) fields.push_back((*m)[1]);
  }
  return fields;
}

bool hasPath(const nlohmann::json& j, const std::string& dotted) {
  const nlohmann::json* node = &j;
  std::istringstream parts(dotted);
  for (std::string key; std::getline(parts, key, '.');) {
    if (!node->is_object() || !node->contains(key)) return false;
    node = &(*node)[key];
  }
  return true;
}

TEST(ForestReadme, ReportsHaveTheFieldsTheFormatDocumentDescribes) {
  const fs::path out = fs::path(FOREST_TEST_OUTPUT) / "cli" / "readme-report";
  const test::CliResult walk = runFromRepository({"walkthrough", "--frames", "4", "--width", "160", "--height", "120", "--quiet", "--out", out.string()});
  ASSERT_EQ(walk.exitCode, 0) << walk.err;
  const nlohmann::json report = nlohmann::json::parse(readTextFile(out / "report.json"));
  const std::vector<std::string> top = documentedFields("## `walkthrough`, `walkthrough --window`, `budget`: `report.json`");
  const std::vector<std::string> record = documentedFields("A frame record:");
  ASSERT_GE(top.size(), 10u);
  ASSERT_GE(record.size(), 15u);
  for (const std::string& field : top) {
    if (field == "input") continue;  // the window report's
    EXPECT_TRUE(hasPath(report, field)) << "report.json lacks documented " << field;
  }
  for (const std::string& field : record) EXPECT_TRUE(hasPath(report["frames"][0], field)) << "frame record lacks documented " << field;

  const fs::path image = fs::path(FOREST_TEST_OUTPUT) / "cli" / "readme-render.png";
  const test::CliResult render = runFromRepository({"render", "--width", "160", "--height", "120", "--out", image.string()});
  ASSERT_EQ(render.exitCode, 0) << render.err;
  const nlohmann::json frame = nlohmann::json::parse(readTextFile(fs::path(image).replace_extension(".json")));
  const std::vector<std::string> renderFields = documentedFields("## `render`: the frame's JSON (default: the image path with `.json`)");
  ASSERT_GE(renderFields.size(), 8u);
  for (const std::string& field : renderFields) EXPECT_TRUE(hasPath(frame, field)) << "render JSON lacks documented " << field;
}

}  // namespace
}  // namespace forest

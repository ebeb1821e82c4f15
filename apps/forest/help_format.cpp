#include "help_format.hpp"

#include <sstream>
#include <vector>

namespace forest::app {

std::string reflow(std::string_view text, std::size_t width) {
  std::string out, line;
  std::size_t start = 0;
  const auto flush = [&] {
    if (!line.empty()) out += line + "\n";
    line.clear();
  };
  while (start < text.size()) {
    // Paragraphs end at a blank line.
    std::size_t end = text.find("\n\n", start);
    if (end == std::string_view::npos) end = text.size();
    std::istringstream words{std::string(text.substr(start, end - start))};
    for (std::string word; words >> word;) {
      if (!line.empty() && line.size() + 1 + word.size() > width) flush();
      line += (line.empty() ? "" : " ") + word;
    }
    flush();
    start = end + 2;
    if (start < text.size()) out += "\n";
  }
  return out;
}

std::string withoutRanges(std::string typeName) {
  // A range validator appends ":TYPE in [low - high]".
  for (std::size_t in = typeName.find(" in ["); in != std::string::npos; in = typeName.find(" in [")) {
    const std::size_t colon = typeName.rfind(':', in);
    const std::size_t close = typeName.find(']', in);
    if (colon == std::string::npos || close == std::string::npos) break;
    typeName.erase(colon, close + 1 - colon);
  }
  return typeName;
}

namespace {

// A row of the options or subcommands table: `left` in the first column_width columns (alone on
// its line when longer), `description` reflowed into the rest, indented under it.
// `text` broken after a comma or a space so that no line passes kHelpWidth columns; the lines after
// the first indented by `indent` spaces.
std::string wrapAtCommas(std::string text, std::size_t indent) {
  std::string out;
  while (text.size() > kHelpWidth) {
    std::size_t at = text.find_last_of(", ", kHelpWidth - 1);
    if (at == std::string::npos || at <= indent) break;
    out += text.substr(0, at + 1) + "\n";
    text = std::string(indent, ' ') + text.substr(at + 1);
  }
  return out + text;
}

std::string tableRow(const std::string& left, const std::string& description, std::size_t column) {
  std::string row = wrapAtCommas("  " + left, 6);
  const std::string indent(column, ' ');
  std::string text = reflow(description, kHelpWidth - column);
  if (text.empty()) return row + "\n";
  if (row.size() + 1 > column || row.find('\n') != std::string::npos) row += "\n" + indent;
  else row += std::string(column - row.size(), ' ');
  for (std::size_t at = text.find('\n'); at != std::string::npos && at + 1 < text.size(); at = text.find('\n', at + 1))
    text.insert(at + 1, indent);
  return row + text;
}

}  // namespace

std::string HelpFormatter::make_option_opts(const CLI::Option* option) const {
  std::string opts = CLI::Formatter::make_option_opts(option);
  const std::string typeName = option->get_type_name();
  if (!typeName.empty()) {
    const std::size_t at = opts.find(typeName);
    if (at != std::string::npos) opts.replace(at, typeName.size(), withoutRanges(typeName));
  }
  return opts;
}

std::string HelpFormatter::make_option(const CLI::Option* option, bool isPositional) const {
  return tableRow(make_option_name(option, isPositional) + make_option_opts(option), make_option_desc(option), get_column_width());
}

std::string HelpFormatter::make_subcommand(const CLI::App* command) const {
  std::string description = command->get_description();
  std::vector<std::string> names;
  for (const CLI::App* sub : command->get_subcommands({})) names.push_back(sub->get_name());
  if (!names.empty()) {
    description += " (";
    for (std::size_t i = 0; i < names.size(); ++i) description += (i ? ", " : "") + names[i];
    description += ")";
  }
  return tableRow(command->get_display_name(true), description, get_column_width());
}

std::string HelpFormatter::make_description(const CLI::App* command) const {
  const std::string description = command->get_description();
  return description.empty() ? std::string() : reflow(description, kHelpWidth);
}

}  // namespace forest::app

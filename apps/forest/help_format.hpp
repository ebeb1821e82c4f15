#pragma once
// How `forest … --help` is laid out: every line at most kHelpWidth columns (descriptions reflowed
// to fit), each option's range said once (in its description, "16 to 8192"; CLI11's type column
// would print it again as "INT:INT in [16 - 8192]"), and a command with subcommands names them.
#include <CLI/CLI.hpp>

#include <string>
#include <string_view>

namespace forest::app {

constexpr std::size_t kHelpWidth = 100;

// `text` reflowed into lines of at most `width` columns (a word longer than that stands alone):
// line breaks within a paragraph become spaces, a blank line keeps paragraphs apart.
std::string reflow(std::string_view text, std::size_t width);

// An option's type as CLI11 names it, less the ranges its validators add:
// "INT:INT in [16 - 8192]" → "INT"; "TEXT:{auto,egl}" stays.
std::string withoutRanges(std::string typeName);

class HelpFormatter : public CLI::Formatter {
 public:
  std::string make_option(const CLI::Option* option, bool isPositional) const override;
  std::string make_option_opts(const CLI::Option* option) const override;
  std::string make_subcommand(const CLI::App* command) const override;
  std::string make_description(const CLI::App* command) const override;
};

}  // namespace forest::app

// Command-line parsing shared by the subcommands: a table of options per command, one usage
// function for every argument error.
#pragma once
#include <map>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vktg::cli {

struct OptionSpec {
  std::string name;        // "--spp"
  std::string valueName;   // "N"; empty for a flag
  std::string help;
  std::string alias = "";  // a short form ("-D"), which also takes its value glued on ("-DNAME=VALUE")
  bool repeatable = false; // may be given several times: every value is kept (ParsedArgs::all)
};

struct CommandSpec {
  std::string name;
  std::string usage;       // "render [SCENE] [options]"
  std::string description;
  std::vector<OptionSpec> options;
  std::string examples;
  size_t maxPositionals = 1;
};

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParsedArgs {
  std::vector<std::string> positionals;
  std::map<std::string, std::string> values;  // option -> value ("" for flags); the last, if repeated
  std::map<std::string, std::vector<std::string>> repeated;  // repeatable option -> every value, in order
  bool has(const std::string& option) const { return values.count(option) != 0; }
  std::optional<std::string> get(const std::string& option) const;
  std::vector<std::string> all(const std::string& option) const;
  // Typed getters throw UsageError naming the option.
  std::optional<double> number(const std::string& option) const;
  std::optional<uint32_t> count(const std::string& option, uint32_t min, uint32_t max) const;
};

ParsedArgs parseArgs(const CommandSpec& spec, const std::vector<std::string>& args);
std::string helpText(const CommandSpec& spec);

}  // namespace vktg::cli

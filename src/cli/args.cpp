#include "cli/args.h"

#include <cmath>
#include <cstdlib>

namespace vktg::cli {

std::optional<std::string> ParsedArgs::get(const std::string& option) const {
  auto it = values.find(option);
  if (it == values.end()) return std::nullopt;
  return it->second;
}

std::vector<std::string> ParsedArgs::all(const std::string& option) const {
  auto it = repeated.find(option);
  return it == repeated.end() ? std::vector<std::string>{} : it->second;
}

std::optional<double> ParsedArgs::number(const std::string& option) const {
  auto text = get(option);
  if (!text) return std::nullopt;
  char* end = nullptr;
  double v = std::strtod(text->c_str(), &end);
  if (text->empty() || *end != '\0' || !std::isfinite(v))
    throw UsageError(option + ": '" + *text + "' is not a finite number");
  return v;
}

std::optional<uint32_t> ParsedArgs::count(const std::string& option, uint32_t min, uint32_t max) const {
  auto text = get(option);
  if (!text) return std::nullopt;
  char* end = nullptr;
  long long v = std::strtoll(text->c_str(), &end, 10);
  if (text->empty() || *end != '\0' || v < min || v > max)
    throw UsageError(option + ": '" + *text + "' must be an integer in [" + std::to_string(min) + ", " +
                     std::to_string(max) + "]");
  return uint32_t(v);
}

ParsedArgs parseArgs(const CommandSpec& spec, const std::vector<std::string>& args) {
  ParsedArgs parsed;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.size() > 1 && arg[0] == '-' && !(arg.size() > 1 && (std::isdigit(arg[1]) || arg[1] == '.'))) {
      std::string name = arg, value;
      bool inlineValue = false;
      const OptionSpec* option = nullptr;
      // A short alias with its value glued on: -DNAME=VALUE.
      for (const auto& o : spec.options)
        if (!o.alias.empty() && !o.valueName.empty() && arg.size() > o.alias.size() && arg.compare(0, o.alias.size(), o.alias) == 0) {
          option = &o;
          value = arg.substr(o.alias.size());
          inlineValue = true;
        }
      if (!option) {
        if (auto eq = arg.find('='); eq != std::string::npos) {
          name = arg.substr(0, eq);
          value = arg.substr(eq + 1);
          inlineValue = true;
        }
        for (const auto& o : spec.options)
          if (o.name == name || (!o.alias.empty() && o.alias == name)) option = &o;
      }
      if (!option) throw UsageError("unknown option '" + name + "' for `vktg " + spec.name + "`");
      name = option->name;
      if (!option->valueName.empty() && !inlineValue) {
        if (i + 1 >= args.size()) throw UsageError(name + " needs a value (" + option->valueName + ")");
        value = args[++i];
      } else if (option->valueName.empty() && inlineValue) {
        throw UsageError(name + " takes no value");
      }
      parsed.values[name] = value;
      if (option->repeatable) parsed.repeated[name].push_back(value);
    } else {
      parsed.positionals.push_back(arg);
    }
  }
  if (parsed.positionals.size() > spec.maxPositionals)
    throw UsageError("unexpected argument '" + parsed.positionals[spec.maxPositionals] + "' for `vktg " + spec.name + "`");
  return parsed;
}

std::string helpText(const CommandSpec& spec) {
  std::string out = "usage: vktg " + spec.usage + "\n\n" + spec.description + "\n\noptions:\n";
  for (const auto& o : spec.options) {
    std::string left = "  " + (o.alias.empty() ? "" : o.alias + ", ") + o.name + (o.valueName.empty() ? "" : " " + o.valueName);
    if (left.size() < 26) left.resize(26, ' ');
    else left += "\n" + std::string(26, ' ');
    out += left + o.help + "\n";
  }
  if (!spec.examples.empty()) out += "\nexamples:\n" + spec.examples;
  return out;
}

}  // namespace vktg::cli

#include "tools/cli/cli.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <sstream>

#include "gonio/version.h"
#include "photometry/format.h"

namespace gonio::cli {
namespace {

// `text` word-wrapped to lines of at most `width` characters, each starting
// with `indent`; line breaks in `text` are kept.
std::string wrap(const std::string& text, const std::string& indent, std::size_t width = 80) {
  std::string out, line;
  const auto flush = [&] {
    out += indent + line + "\n";
    line.clear();
  };
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    std::istringstream words(text.substr(start, end - start));
    for (std::string word; words >> word;) {
      if (!line.empty() && indent.size() + line.size() + 1 + word.size() > width) flush();
      line += (line.empty() ? "" : " ") + word;
    }
    flush();
    start = end + 1;
  }
  return out;
}

}  // namespace

ArgParser::ArgParser(std::string command, std::string synopsis, std::string description)
    : command_(std::move(command)),
      synopsis_(std::move(synopsis)),
      description_(std::move(description)) {}

void ArgParser::flag(const std::string& name, bool* out, const std::string& help) {
  options_.push_back({name, "", help, [out](const std::string&) -> std::optional<std::string> {
                        *out = true;
                        return std::nullopt;
                      }});
}

void ArgParser::option(const std::string& name, std::string* out, const std::string& metavar,
                       const std::string& help) {
  options_.push_back(
      {name, metavar, help, [out](const std::string& v) -> std::optional<std::string> {
         *out = v;
         return std::nullopt;
       }});
}

void ArgParser::option(const std::string& name, long long* out, long long min, long long max,
                       const std::string& metavar, const std::string& help) {
  options_.push_back(
      {name, metavar, help,
       [out, min, max, name](const std::string& v) -> std::optional<std::string> {
         long long value = 0;
         const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), value);
         if (ec != std::errc() || end != v.data() + v.size())
           return "--" + name + " needs an integer, got '" + v + "'";
         if (value < min || value > max)
           return "--" + name + " must be between " + std::to_string(min) + " and " +
                  std::to_string(max) + ", got " + v;
         *out = value;
         return std::nullopt;
       }});
}

void ArgParser::option(const std::string& name, double* out, double min, double max,
                       const std::string& metavar, const std::string& help) {
  options_.push_back(
      {name, metavar, help,
       [out, min, max, name](const std::string& v) -> std::optional<std::string> {
         double value = 0.0;
         const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), value);
         if (ec != std::errc() || end != v.data() + v.size() || !(value == value))
           return "--" + name + " needs a number, got '" + v + "'";
         if (value < min || value > max)
           return "--" + name + " must be between " + format_number(min) + " and " +
                  format_number(max) + ", got " + v;
         *out = value;
         return std::nullopt;
       }});
}

void ArgParser::choice(const std::string& name, std::string* out, std::vector<std::string> choices,
                       const std::string& help) {
  std::string metavar;
  for (const auto& c : choices) metavar += (metavar.empty() ? "" : "|") + c;
  options_.push_back(
      {name, metavar, help,
       [out, choices, name, metavar](const std::string& v) -> std::optional<std::string> {
         for (const auto& c : choices) {
           if (c == v) {
             *out = v;
             return std::nullopt;
           }
         }
         return "--" + name + " must be one of " + metavar + ", got '" + v + "'";
       }});
}

void ArgParser::positional(const std::string& name, std::string* out, const std::string& help) {
  positionals_.push_back({name, help, out, nullptr, 1});
}

void ArgParser::positional_list(const std::string& name, std::vector<std::string>* out,
                                std::size_t min_count, const std::string& help) {
  positionals_.push_back({name, help, nullptr, out, min_count});
}

ArgParser::Option* ArgParser::find(const std::string& name) {
  for (Option& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

bool ArgParser::given(const std::string& name) const {
  for (const Option& o : options_)
    if (o.name == name) return o.seen;
  return false;
}

ArgParser::Outcome ArgParser::parse(const std::vector<std::string>& args) {
  auto usage_error = [&](const std::string& message) {
    print_error(command_ + ": " + message);
    std::fprintf(stderr, "%s\nTry '%s %s --help'.\n", usage().c_str(), kProgramName,
                 command_.c_str());
    return Outcome::Error;
  };

  std::vector<std::string> positionals;
  bool only_positionals = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (only_positionals || arg.size() < 2 || arg[0] != '-' || arg == "-") {
      positionals.push_back(arg);
      continue;
    }
    if (arg == "--") {
      only_positionals = true;
      continue;
    }
    if (arg == "--help" || arg == "-h") {
      std::fputs(help().c_str(), stdout);
      return Outcome::Help;
    }
    if (arg.rfind("--", 0) != 0) return usage_error("unknown option '" + arg + "'");
    std::string name = arg.substr(2), value;
    bool has_value = false;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_value = true;
    }
    Option* opt = find(name);
    if (!opt) return usage_error("unknown option '--" + name + "'");
    if (opt->metavar.empty()) {
      if (has_value) return usage_error("option '--" + name + "' takes no value");
    } else if (!has_value) {
      if (i + 1 >= args.size()) return usage_error("option '--" + name + "' needs a value");
      value = args[++i];
    }
    if (auto problem = opt->set(value)) return usage_error(*problem);
    opt->seen = true;
  }

  std::size_t next = 0;
  for (const Positional& p : positionals_) {
    if (p.list) {
      p.list->assign(positionals.begin() + static_cast<std::ptrdiff_t>(next), positionals.end());
      if (p.list->size() < p.min_count) return usage_error("missing " + p.name);
      next = positionals.size();
    } else {
      if (next >= positionals.size()) return usage_error("missing " + p.name);
      *p.out = positionals[next++];
    }
  }
  if (next < positionals.size()) return usage_error("unexpected argument '" + positionals[next] + "'");
  return Outcome::Run;
}

std::string ArgParser::usage() const {
  return std::string("Usage: ") + kProgramName + " " + command_ + " " + synopsis_;
}

std::string ArgParser::help() const {
  std::ostringstream s;
  s << usage() << "\n\n" << description_ << "\n";
  if (!positionals_.empty()) {
    s << "\nArguments:\n";
    for (const Positional& p : positionals_) s << "  " << p.name << "\n" << wrap(p.help, "      ");
  }
  s << "\nOptions:\n";
  for (const Option& o : options_) {
    s << "  --" << o.name;
    if (!o.metavar.empty()) s << " " << o.metavar;
    s << "\n" << wrap(o.help, "      ");
  }
  s << "  --help\n      Show this help and exit.\n";
  return s.str();
}

}  // namespace gonio::cli

#include "cli_args.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>

namespace hail::bench {
namespace {

/// The whole of `text` as a finite number (digits, a decimal point, an exponent), or nothing.
std::optional<double> read_number(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::string format_real(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", x);
  return buffer;
}

// Appended piece by piece: GCC 12 warns (-Wrestrict, a known false positive) about
// "literal" + std::string temporaries.
std::string range_text(char open, const std::string& min, const std::string& max) {
  std::string text(1, open);
  text.append(min).append(", ").append(max).append("]");
  return text;
}

std::string real_range(double min, double max, bool exclude_min) {
  return range_text(exclude_min ? '(' : '[', format_real(min), format_real(max));
}

std::string count_range(long long min, long long max) { return range_text('[', std::to_string(min), std::to_string(max)); }

}  // namespace

long long parse_count(std::string_view flag, const std::string& text, long long min, long long max) {
  const std::optional<double> v = read_number(text);
  // Compared as doubles: exact for every whole number up to 2^53, far beyond any range here.
  if (!v || *v != std::floor(*v) || *v < double(min) || *v > double(max))
    throw std::invalid_argument(std::string(flag) + " must be a whole number in " + count_range(min, max) + ", got '" +
                                text + "'");
  return static_cast<long long>(*v);
}

double parse_real(std::string_view flag, const std::string& text, double min, double max, bool exclude_min) {
  const std::optional<double> v = read_number(text);
  if (!v || *v < min || (exclude_min && *v == min) || *v > max)
    throw std::invalid_argument(std::string(flag) + " must be a number in " + real_range(min, max, exclude_min) +
                                ", got '" + text + "'");
  return *v;
}

ArgParser::ArgParser(std::string command, std::string what) : command_(std::move(command)), what_(std::move(what)) {}

std::string ArgParser::describe_count(const std::string& help, long long min, long long max) {
  return help + " (whole number in " + count_range(min, max) + ")";
}

std::string ArgParser::describe_real(const std::string& help, double min, double max, bool exclude_min) {
  return help + " (in " + real_range(min, max, exclude_min) + ")";
}

ArgParser& ArgParser::flag(std::string name, bool& target, std::string help) {
  options_.push_back({std::move(name), "", std::move(help), [&target](const std::string&) { target = true; }});
  return *this;
}

ArgParser& ArgParser::text(std::string name, std::string& target, std::string value_name, std::string help) {
  return custom(std::move(name), std::move(value_name), std::move(help), [&target](const std::string& v) { target = v; });
}

ArgParser& ArgParser::choice(std::string name, std::string& target, std::vector<std::string> choices, std::string help) {
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : "|") + c;
  return custom(name, list, std::move(help), [&target, name, choices, list](const std::string& v) {
    for (const std::string& c : choices)
      if (v == c) return void(target = v);
    throw std::invalid_argument(name + " must be one of " + list + ", got '" + v + "'");
  });
}

ArgParser& ArgParser::custom(std::string name, std::string value_name, std::string help,
                             std::function<void(const std::string&)> apply) {
  options_.push_back({std::move(name), std::move(value_name), std::move(help), std::move(apply)});
  return *this;
}

ArgParser& ArgParser::positional(std::string name, std::string& target, std::string help) {
  positional_name_ = std::move(name), positional_help_ = std::move(help), positional_ = &target;
  return *this;
}

const ArgParser::Option* ArgParser::find(std::string_view name) const {
  for (const Option& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

bool ArgParser::parse(const std::vector<std::string>& args) {
  const std::string see = " (see hail-bench " + command_ + " --help)";
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& arg = args[k];
    if (arg == "--help" || arg == "-h") {
      std::fputs(usage().c_str(), stdout);
      return false;
    }
    if (arg.empty() || arg[0] != '-') {
      if (!positional_ || given(positional_name_))
        throw std::invalid_argument("unexpected argument '" + arg + "' for hail-bench " + command_ + see);
      *positional_ = arg;
      given_.insert(positional_name_);
      continue;
    }
    const std::size_t equals = arg.find('=');  // --flag=value is --flag value
    const std::string name = arg.substr(0, equals);
    const Option* option = find(name);
    if (!option) throw std::invalid_argument("unknown option '" + name + "' for hail-bench " + command_ + see);
    if (option->value_name.empty()) {
      if (equals != std::string::npos) throw std::invalid_argument(name + " takes no value, got '" + arg + "'");
      option->apply("");
    } else if (equals != std::string::npos) {
      option->apply(arg.substr(equals + 1));
    } else {
      if (k + 1 >= args.size()) throw std::invalid_argument(name + " needs a value (" + option->value_name + ")" + see);
      option->apply(args[++k]);
    }
    given_.insert(name);
  }
  return true;
}

std::string ArgParser::usage() const {
  std::string text = "usage: hail-bench " + command_;
  if (positional_) text += " [" + positional_name_ + "]";
  text += " [options]\n  " + what_ + "\n\n";
  auto line = [&](const std::string& left, const std::string& help) {
    text += "  " + left;
    text += left.size() < 24 ? std::string(24 - left.size(), ' ') : "\n" + std::string(26, ' ');  // a long one: help below
    text += help + "\n";
  };
  if (positional_) line(positional_name_, positional_help_);
  for (const Option& o : options_) line(o.name + (o.value_name.empty() ? "" : " " + o.value_name), o.help);
  line("--simd PATH", "run the SIMD kernels of PATH (sse4.2|avx2|avx512; any command)");
  line("--help", "this text");
  return text;
}

}  // namespace hail::bench

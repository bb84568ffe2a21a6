#include "cli.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "scenes/scenes.h"

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

std::string count_range(long long min, long long max) {
  return range_text('[', std::to_string(min), std::to_string(max));
}

std::string real_range(double min, double max, bool exclude_min) {
  return range_text(exclude_min ? '(' : '[', format_real(min), format_real(max));
}

/// Empty if `text` is a whole number in [min, max] (written back as plain digits), else why not.
std::string check_count(std::string& text, long long min, long long max) {
  const std::optional<double> v = read_number(text);
  // Compared as doubles: exact for every whole number up to 2^53, far beyond any range here.
  if (!v || *v != std::floor(*v) || *v < double(min) || *v > double(max))
    return "must be a whole number in " + count_range(min, max) + ", got '" + text + "'";
  text = std::to_string(static_cast<long long>(*v));
  return {};
}

std::string check_real(const std::string& text, double min, double max, bool exclude_min) {
  const std::optional<double> v = read_number(text);
  if (!v || *v < min || (exclude_min && *v == min) || *v > max)
    return "must be a number in " + real_range(min, max, exclude_min) + ", got '" + text + "'";
  return {};
}

}  // namespace

CLI::Validator whole_number_in(long long min, long long max) {
  return CLI::Validator([min, max](std::string& text) { return check_count(text, min, max); },
                        "whole number in " + count_range(min, max));
}

CLI::Validator number_in(double min, double max, bool exclude_min) {
  return CLI::Validator([min, max, exclude_min](std::string& text) { return check_real(text, min, max, exclude_min); },
                        "in " + real_range(min, max, exclude_min));
}

long long parse_count(const std::string& what, const std::string& text, long long min, long long max) {
  std::string value = text;
  const std::string error = check_count(value, min, max);
  if (!error.empty()) throw std::invalid_argument(what + ": " + error);
  return std::stoll(value);
}

std::vector<long long> parse_count_list(const std::string& what, const std::string& text, long long min,
                                        long long max) {
  std::vector<long long> counts;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) counts.push_back(parse_count(what, item, min, max));
  return counts;
}

double parse_real(const std::string& what, const std::string& text, double min, double max, bool exclude_min) {
  const std::string error = check_real(text, min, max, exclude_min);
  if (!error.empty()) throw std::invalid_argument(what + ": " + error);
  return std::strtod(text.c_str(), nullptr);
}

void use_bench_conventions(CLI::App& app) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)->always_capture_default();
  app.footer("--simd sse4.2|avx2|avx512 (any command) runs the SIMD kernels of that path (hail-bench --help)");
}

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  for (const SceneEntry& s : scene_registry()) names.emplace_back(s.name);
  return names;
}

bool parse_command_line(CLI::App& app, const std::vector<std::string>& args) {
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return false;
  } catch (const CLI::ParseError& e) {
    throw std::invalid_argument(std::string(e.what()) + " (see " + app.get_name() + " --help)");
  }
  return true;
}

}  // namespace hail::bench

#pragma once
// The one command-line parser of every hail-bench command. A command declares its flags (each
// with a help line and, for numbers, the range it accepts) and gets the same strict checks:
// a count must be a whole number in its range ("1e6" is one, "2.7" and "1e10" are refused),
// an unknown flag is an error naming it, `--help` prints the command's own usage. Every error
// is a std::invalid_argument naming the flag, the range and the text given (main turns it
// into exit status 2). Hand-written rather than CLI11: a hundred lines that say exactly what
// the messages are, and no dependency for a benchmark tool.

#include <concepts>
#include <functional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace hail::bench {

/// A whole number in [min, max], written as digits or in exponent form ("1e6"); otherwise
/// std::invalid_argument: "--steps must be a whole number in [1, 100000000], got '2.7'".
[[nodiscard]] long long parse_count(std::string_view flag, const std::string& text, long long min, long long max);

/// A finite number in [min, max] ((min, max] with exclude_min); otherwise std::invalid_argument
/// naming the flag, the range and the text.
[[nodiscard]] double parse_real(std::string_view flag, const std::string& text, double min, double max,
                                bool exclude_min = false);

class ArgParser {
 public:
  /// `command` as typed after hail-bench ("run"); `what` is the first line of its --help.
  ArgParser(std::string command, std::string what);

  /// A flag without a value: sets `target` to true.
  ArgParser& flag(std::string name, bool& target, std::string help);
  /// A whole number in [min, max] (parse_count).
  template <std::integral T>
  ArgParser& count(std::string name, T& target, long long min, long long max, std::string help) {
    return custom(name, "N", describe_count(help, min, max),
                  [&target, name, min, max](const std::string& v) { target = static_cast<T>(parse_count(name, v, min, max)); });
  }
  /// A number in [min, max], or (min, max] with exclude_min (parse_real).
  template <std::floating_point T>
  ArgParser& number(std::string name, T& target, double min, double max, std::string help, bool exclude_min = false) {
    return custom(name, "X", describe_real(help, min, max, exclude_min),
                  [&target, name, min, max, exclude_min](const std::string& v) {
                    target = static_cast<T>(parse_real(name, v, min, max, exclude_min));
                  });
  }
  /// Any text (a path, a name checked later).
  ArgParser& text(std::string name, std::string& target, std::string value_name, std::string help);
  /// One of `choices`.
  ArgParser& choice(std::string name, std::string& target, std::vector<std::string> choices, std::string help);
  /// A value that `apply` reads (and checks, throwing std::invalid_argument).
  ArgParser& custom(std::string name, std::string value_name, std::string help, std::function<void(const std::string&)> apply);
  /// The one argument not starting with '-' (at most one; optional).
  ArgParser& positional(std::string name, std::string& target, std::string help);

  /// Reads `args`; false if --help (or -h) was among them and the usage was printed, so the
  /// command should return 0 without running. The last of a repeated flag wins.
  [[nodiscard]] bool parse(const std::vector<std::string>& args);
  /// Whether the flag (or the positional, by its name) was on the command line.
  [[nodiscard]] bool given(std::string_view name) const { return given_.contains(name); }
  /// The text --help prints.
  [[nodiscard]] std::string usage() const;

 private:
  struct Option {
    std::string name, value_name, help;  // value_name empty: a flag without a value
    std::function<void(const std::string&)> apply;
  };
  static std::string describe_count(const std::string& help, long long min, long long max);
  static std::string describe_real(const std::string& help, double min, double max, bool exclude_min);
  const Option* find(std::string_view name) const;

  std::string command_, what_;
  std::vector<Option> options_;
  std::string positional_name_, positional_help_;
  std::string* positional_ = nullptr;
  std::set<std::string, std::less<>> given_;
};

}  // namespace hail::bench

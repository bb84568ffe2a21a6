#pragma once
// Numbers and names inside a hail-bench flag's value (a comma-separated list of counts or time
// steps), checked by the same rules as whole flags (bench/cli.h), without CLI11 (bench/cli.h
// says what it costs to compile).

#include <string>
#include <vector>

namespace hail::bench {

/// The text as a whole number in [min, max] (whole_number_in's rule), for a value inside a list;
/// std::invalid_argument naming `what` otherwise.
[[nodiscard]] long long parse_count(const std::string& what, const std::string& text, long long min, long long max);
/// A comma-separated list of such whole numbers ("4000,64000"); empty text gives an empty list.
[[nodiscard]] std::vector<long long> parse_count_list(const std::string& what, const std::string& text, long long min,
                                                      long long max);
/// The text as a finite number in [min, max] ((min, max] with exclude_min); std::invalid_argument otherwise.
[[nodiscard]] double parse_real(const std::string& what, const std::string& text, double min, double max,
                                bool exclude_min = false);

/// The built-in scene names (hail-bench --help lists them), for CLI::IsMember.
[[nodiscard]] std::vector<std::string> scene_names();

}  // namespace hail::bench

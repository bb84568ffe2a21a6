#pragma once
// How many random samples a brute-force comparison test draws. The sanitizer stages
// (scripts/sanitizers.sh) set HAIL_TEST_SAMPLE_DIVISOR=5: the same exact comparisons on a fifth
// of the samples, because these few tests took most of the ASan stage's time (the BVH query test
// alone 92 s of the suite's 179 s on 2 cores), and the sanitizers look for memory and UB faults,
// which the first fifth of the queries reach as well. Unset (Release, plain ctest): every test
// draws its full count.

#include <algorithm>
#include <cstdlib>

namespace hail::test {

/// `full`, divided by HAIL_TEST_SAMPLE_DIVISOR when that is set to an integer >= 1; at least 1.
inline int sample_count(int full) {
  static const int divisor = [] {
    const char* text = std::getenv("HAIL_TEST_SAMPLE_DIVISOR");
    const int d = text != nullptr ? std::atoi(text) : 1;
    return std::max(d, 1);
  }();
  return std::max(1, full / divisor);
}

}  // namespace hail::test

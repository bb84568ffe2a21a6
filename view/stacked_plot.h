#pragma once
// The per-phase plot's layout: each sample's phases stacked bottom to top, so that a column's
// top is the step's whole time and each band one phase's share. No ImGui here (hail-view-tests
// checks it); panel.cpp draws the bands.

#include <algorithm>
#include <span>
#include <vector>

namespace hail::view {

/// series[k][i]: phase k's value at sample i (every series the same length). Returns, per
/// sample i, the running sums tops[i * (series + 1) + k] = series[0][i] + ... + series[k - 1][i]
/// (k = 0: 0, the column's foot; k = series: its top). Negative values count as 0.
[[nodiscard]] inline std::vector<float> stack_series(std::span<const std::vector<float>> series) {
  const std::size_t samples = series.empty() ? 0 : series[0].size(), bands = series.size();
  std::vector<float> tops(samples * (bands + 1), 0.0f);
  for (std::size_t i = 0; i < samples; ++i) {
    float sum = 0.0f;
    for (std::size_t k = 0; k < bands; ++k) {
      tops[i * (bands + 1) + k] = sum;
      sum += i < series[k].size() ? std::max(series[k][i], 0.0f) : 0.0f;
    }
    tops[i * (bands + 1) + bands] = sum;
  }
  return tops;
}

}  // namespace hail::view

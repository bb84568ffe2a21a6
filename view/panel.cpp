#include "view/panel.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <thread>

#include "view/stacked_plot.h"

namespace hail::view {

void Plots::push(std::vector<float>& v, float x) {
  if (v.size() == kLength) v.erase(v.begin());
  v.push_back(x);
}

void Plots::add_step(const Frame& f) {
  const PhaseTimes& p = f.phase_ms;
  const double values[kPhases] = {p.reorder, p.predict,   p.detect_terrain, p.detect_pairs, p.solve,
                                  p.sweep,   p.integrate, p.depenetrate,    p.islands};
  for (int k = 0; k < kPhases; ++k) push(phases_[std::size_t(k)], float(values[k]));
  push(step_ms_, float(f.step_ms));
  push(energy_, float(f.kinetic_energy));
  push(overlap_, float(f.deepest_overlap));
  push(tunnelled_, float(f.tunnelled));
}

void Plots::add_draw(double ms) { push(draw_ms_, float(ms)); }

void Plots::draw() const {
  auto plot = [](const char* label, const std::vector<float>& v, const char* unit) {
    const float last = v.empty() ? 0.0f : v.back();
    char overlay[64];
    std::snprintf(overlay, sizeof overlay, "%.3g %s", last, unit);
    ImGui::PlotLines(label, v.data(), int(v.size()), 0, overlay, 0.0f, FLT_MAX, ImVec2(0, 50));
  };
  if (!step_ms_.empty()) plot("step", step_ms_, "ms");  // (a replay has no steps)
  plot("draw", draw_ms_, "ms");
  if (!step_ms_.empty() && ImGui::CollapsingHeader("step phases (ms), stacked", ImGuiTreeNodeFlags_DefaultOpen))
    draw_phases();
  if (!energy_.empty()) {
    plot("kinetic", energy_, "J");
    plot("overlap", overlap_, "m deepest");
    plot("tunnelled", tunnelled_, "spheres");
  }
}

namespace {

/// Band colours, one per phase: distinct hues, in order round the wheel.
ImU32 phase_colour(int k) {
  const float hue = float(k) / float(Plots::kPhases);
  float r = 0, g = 0, b = 0;
  ImGui::ColorConvertHSVtoRGB(hue, 0.65f, 0.9f, r, g, b);
  return ImGui::ColorConvertFloat4ToU32(ImVec4(r, g, b, 1.0f));
}

}  // namespace

void Plots::draw_phases() const {
  const std::vector<float> tops = stack_series(phases_);
  const std::size_t samples = phases_[0].size(), stride = kPhases + 1;
  float highest = 1e-3f;
  for (std::size_t i = 0; i < samples; ++i) highest = std::max(highest, tops[i * stride + kPhases]);
  const ImVec2 size(240.0f, 110.0f);
  const ImVec2 at = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(at, ImVec2(at.x + size.x, at.y + size.y), ImGui::GetColorU32(ImGuiCol_FrameBg));
  // The newest step at the right edge; a column per step.
  const float column = size.x / float(kLength), left = at.x + size.x - column * float(samples);
  const auto y_of = [&](float ms) { return at.y + size.y - size.y * ms / highest; };
  for (std::size_t i = 0; i < samples; ++i) {
    const float x0 = left + column * float(i), x1 = x0 + std::max(column, 1.0f);
    for (int k = 0; k < kPhases; ++k) {
      const float foot = tops[i * stride + std::size_t(k)], top = tops[i * stride + std::size_t(k) + 1];
      if (top > foot) draw->AddRectFilled(ImVec2(x0, y_of(top)), ImVec2(x1, y_of(foot)), phase_colour(k));
    }
  }
  char scale[32];
  std::snprintf(scale, sizeof scale, "%.3g ms", highest);
  draw->AddText(ImVec2(at.x + 2, at.y + 1), ImGui::GetColorU32(ImGuiCol_Text), scale);
  ImGui::Dummy(size);
  // The draw time beside it, on its own scale.
  ImGui::SameLine();
  char overlay[32];
  std::snprintf(overlay, sizeof overlay, "draw %.3g ms", draw_ms_.empty() ? 0.0f : draw_ms_.back());
  ImGui::PlotHistogram("##draw", draw_ms_.data(), int(draw_ms_.size()), 0, overlay, 0.0f, FLT_MAX, ImVec2(90, size.y));
  // The legend, three to a row: each phase's colour, name and last value.
  const float x0 = ImGui::GetCursorPosX();
  for (int k = 0; k < kPhases; ++k) {
    const std::vector<float>& v = phases_[std::size_t(k)];
    if (k % 3 != 0) ImGui::SameLine(x0 + float(k % 3) * 165.0f);
    ImGui::ColorButton(kPhaseNames[std::size_t(k)], ImGui::ColorConvertU32ToFloat4(phase_colour(k)),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(10, 10));
    ImGui::SameLine();
    ImGui::Text("%s %.2f", kPhaseNames[std::size_t(k)], v.empty() ? 0.0f : v.back());
  }
}

void live_panel(const std::string& title, const Frame& frame, LiveSimulation& sim, LiveControls& c, Renderer& renderer,
                const Plots& plots, int bvh_depth) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("hail", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s", title.c_str());
  ImGui::Text("%zu spheres, step %llu, %d threads", frame.size(), static_cast<unsigned long long>(frame.step),
              sim.thread_count());
  if (ImGui::Checkbox("pause", &c.paused)) sim.set_paused(c.paused);
  ImGui::SameLine();
  if (ImGui::Button("step")) {
    c.paused = true;
    sim.set_paused(true);
    sim.step_once();
  }
  ImGui::SameLine();
  if (ImGui::Button("reset")) sim.reset();
  // Sphere count and pair search shape the scene as it is built: they take effect on reset.
  static constexpr const char* kSearches[] = {"automatic", "brute force", "grid", "sweep and prune", "bvh"};
  static constexpr PairSearch kSearchValues[] = {PairSearch::Automatic, PairSearch::BruteForce, PairSearch::Grid,
                                                 PairSearch::SweepAndPrune, PairSearch::Bvh};
  bool chosen = ImGui::InputInt("spheres", &c.spheres, 100, 1000);
  c.spheres = std::clamp(c.spheres, 1, 10'000'000);
  chosen |= ImGui::Combo("pair search", &c.pair_search, kSearches, IM_ARRAYSIZE(kSearches));
  chosen |= ImGui::Checkbox("sleeping", &c.sleep);
  if (chosen) sim.choose_for_reset(std::size_t(c.spheres), kSearchValues[c.pair_search], c.sleep);
  ImGui::TextDisabled("(spheres, pair search and sleeping: on reset)");
  if (ImGui::SliderFloat("time scale", &c.speed, 0.02f, 4.0f, "%.2f x real time", ImGuiSliderFlags_Logarithmic))
    sim.set_speed(c.speed);
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  ImGui::SliderInt("threads", &c.threads, 1, cores);
  if (ImGui::IsItemDeactivatedAfterEdit()) sim.set_threads(c.threads);
  ImGui::SliderFloat("restitution", &c.restitution, 0.0f, 1.0f);
  if (ImGui::IsItemDeactivatedAfterEdit()) sim.set_material(c.restitution, c.friction);
  ImGui::SliderFloat("friction", &c.friction, 0.0f, 2.0f);
  if (ImGui::IsItemDeactivatedAfterEdit()) sim.set_material(c.restitution, c.friction);
  ImGui::SliderFloat("red at", &renderer.max_speed, 0.1f, 100.0f, "%.1f m/s", ImGuiSliderFlags_Logarithmic);
  static constexpr const char* kColours[] = {"speed", "island", "sleep (asleep grey)"};
  int colour = int(renderer.colour_mode);
  if (ImGui::Combo("colour", &colour, kColours, IM_ARRAYSIZE(kColours))) renderer.colour_mode = ColourMode(colour);
  ImGui::Checkbox("contact normals", &c.draw.normals);
  ImGui::SameLine();
  ImGui::Checkbox("grid cells", &c.draw.grid);
  if (bvh_depth >= 0) {
    bool bvh = c.draw.bvh_depth >= 0;
    ImGui::Checkbox("BVH boxes", &bvh);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(120);
    ImGui::SliderInt("depth", &c.bvh_depth, 0, bvh_depth);
    c.draw.bvh_depth = bvh ? c.bvh_depth : -1;
  }
  if (c.draw.grid && frame.grid_cells.empty())
    ImGui::TextDisabled("(no grid cells: the last step did not use the grid)");
  sim.set_capture(capture_for(renderer.colour_mode, c.draw));
  plots.draw();
  ImGui::TextDisabled("left drag: orbit, right drag: pan, wheel: zoom");
  ImGui::TextDisabled("shift + click: drop spheres there; F: fire a fast sphere at the cursor");
  ImGui::End();
}

bool replay_panel(const std::string& title, const std::string& note, int frame_count, const Frame& frame,
                  ReplayControls& c, Renderer& renderer, const Plots& plots) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("hail replay", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::Text("%s", title.c_str());
  if (!note.empty()) ImGui::TextWrapped("%s", note.c_str());
  ImGui::Text("%zu spheres, step %llu", frame.size(), static_cast<unsigned long long>(frame.step));
  ImGui::Checkbox("play", &c.playing);
  const bool scrubbed = ImGui::SliderInt("frame", &c.frame, 0, std::max(frame_count - 1, 0));
  if (scrubbed) c.playing = false;
  ImGui::SliderFloat("frames/s", &c.frames_per_second, 1.0f, 120.0f, "%.0f");
  ImGui::SliderFloat("red at", &renderer.max_speed, 0.1f, 100.0f, "%.1f m/s", ImGuiSliderFlags_Logarithmic);
  plots.draw();
  ImGui::TextDisabled("left drag: orbit, right drag: pan, wheel: zoom");
  ImGui::End();
  return scrubbed;
}

}  // namespace hail::view

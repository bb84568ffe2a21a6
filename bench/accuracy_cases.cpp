#include "accuracy_cases.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace hail::bench {
namespace {

constexpr double kG = 9.81;

/// A. Bounce: r 0.5, m 1, lowest point dropped from 10 m onto flat ground, e 0.8, no friction.
/// Apex n of the lowest point is 10 e^(2n); the error is the worst of apexes 1..3. The ground is
/// a plane, or with `terrain` a flat heightmap: a plane's impact is solved at its time, a
/// terrain contact is speculative and the collision pass bounces the sphere before it reaches
/// the ground (docs/accuracy.md, "Terrain bounces").
class Bounce final : public AccuracyCase {
 public:
  explicit Bounce(bool terrain) : terrain_(terrain) {}
  std::string name() const override { return terrain_ ? "A-bounce-terrain" : "A-bounce"; }
  std::string summary() const override {
    return terrain_ ? "the same drop onto flat terrain (speculative contacts): 10 e^(2n)"
                    : "apexes 1..3 of a ball dropped from 10 m, e = 0.8: 10 e^(2n)";
  }
  PeerScene scene() const override {
    PeerScene s;
    s.name = name();
    if (terrain_) {
      s.heightmap = std::make_shared<const Heightmap>(
          Heightmap::from_function(33, 33, {.cell_x = 1.0f, .cell_z = 1.0f, .origin_x = -16.0f, .origin_z = -16.0f},
                                   [](float, float) { return 0.0f; }));
      s.terrain_restitution = 0.8f, s.terrain_friction = 0.0f;
    } else {
      s.planes.push_back({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.8f, .friction = 0.0f});
    }
    // On terrain, off its grid lines and vertices.
    const Vec3 start = terrain_ ? Vec3{0.3f, 10.5f, 0.2f} : Vec3{0.0f, 10.5f, 0.0f};
    s.spheres.push_back({.position = start, .radius = 0.5f, .mass = 1, .restitution = 0.8f, .friction = 0.0f});
    return s;
  }
  double duration() const override { return 6.6; }  // apex 3 at about 6.27 s
  void reset() override { apexes_.clear(), prev_y_ = 10.5, prev_vy_ = 0.0; }
  void observe(const std::vector<PeerState>& state, double) override {
    const double y = state[0].position.y(), vy = state[0].velocity.y();
    if (prev_vy_ > 0.0 && vy <= 0.0) apexes_.push_back(std::max(prev_y_, y) - 0.5);  // an apex since the last frame
    prev_y_ = y, prev_vy_ = vy;
  }
  double error() const override {
    if (apexes_.size() < 3) return 1.0;
    double worst = 0.0;
    for (int n = 1; n <= 3; ++n) {
      const double exact = 10.0 * std::pow(0.8, 2 * n);
      worst = std::max(worst, std::fabs(apexes_[static_cast<std::size_t>(n - 1)] - exact) / exact);
    }
    return worst;
  }

 private:
  bool terrain_;
  std::vector<double> apexes_;
  double prev_y_ = 10.5, prev_vy_ = 0.0;
};

/// B. Slide to roll: v0 = 5 m/s, w0 = 0, mu = 0.3 on flat ground. Slides until
/// t* = 2 v0 / (7 mu g), then rolls at 5/7 v0. Error: the worse of the two, relative.
class SlideToRoll final : public AccuracyCase {
 public:
  std::string name() const override { return "B-slide-to-roll"; }
  std::string summary() const override { return "v0 5 m/s, mu 0.3: rolls from t* = 0.4854 s at 3.5714 m/s"; }
  PeerScene scene() const override {
    PeerScene s;
    s.name = name();
    s.planes.push_back({.normal = {0, 1, 0}, .offset = 0, .restitution = 0.0f, .friction = 0.3f});
    s.spheres.push_back({.position = {0, 0.5f, 0},
                         .velocity = {5, 0, 0},
                         .radius = 0.5f,
                         .mass = 1,
                         .restitution = 0.0f,
                         .friction = 0.3f});
    return s;
  }
  double duration() const override { return 1.0; }
  void reset() override { t_star_ = -1.0, slip_.clear(), times_.clear(), v_end_ = 0.0; }
  void observe(const std::vector<PeerState>& state, double t) override {
    // Slip of the contact point along x: v + w x (0, -r, 0) = vx + wz r.
    const double slip = state[0].velocity.x() + state[0].angular_velocity.z() * 0.5;
    if (t_star_ < 0.0 && slip <= 1e-3 && slip_.size() >= 2) {
      // Slip falls linearly while sliding: extrapolate the last two sliding frames to zero, so
      // the answer does not snap to the frame grid.
      const double s1 = slip_[slip_.size() - 2], s2 = slip_.back();
      const double t1 = times_[times_.size() - 2], t2 = times_.back();
      t_star_ = s1 > s2 ? t2 + s2 * (t2 - t1) / (s1 - s2) : t2;
    }
    slip_.push_back(slip), times_.push_back(t);
    v_end_ = state[0].velocity.x();
  }
  double error() const override {
    const double t_exact = 2.0 * 5.0 / (7.0 * 0.3 * kG), v_exact = 5.0 * 5.0 / 7.0;
    if (t_star_ < 0.0) return 1.0;
    return std::max(std::fabs(t_star_ - t_exact) / t_exact, std::fabs(v_end_ - v_exact) / v_exact);
  }

 private:
  double t_star_ = -1.0, v_end_ = 0.0;
  std::vector<double> slip_, times_;
};

/// C. Head-on: no gravity, m1 = 1 at x = -2 at +10 m/s, m2 at rest at x = 2, e = 1.
class HeadOn final : public AccuracyCase {
 public:
  explicit HeadOn(float m2) : m2_(m2) {}
  std::string name() const override { return m2_ == 1.0f ? "C-head-on-m2-1" : "C-head-on-m2-1000"; }
  std::string summary() const override { return "1-D elastic: v1' = (m1 - m2)/(m1 + m2) 10, v2' = 2 m1/(m1 + m2) 10"; }
  PeerScene scene() const override {
    PeerScene s;
    s.name = name();
    s.gravity = Vec3(0, 0, 0);
    s.spheres.push_back(
        {.position = {-2, 0, 0}, .velocity = {10, 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 1, .friction = 0});
    s.spheres.push_back({.position = {2, 0, 0}, .radius = 0.5f, .mass = m2_, .restitution = 1, .friction = 0});
    return s;
  }
  double duration() const override { return 1.0; }
  void reset() override { v1_ = v2_ = 0.0; }
  void observe(const std::vector<PeerState>& state, double) override {
    v1_ = state[0].velocity.x(), v2_ = state[1].velocity.x();
  }
  double error() const override {
    const double m1 = 1.0, m2 = m2_;
    const double e1 = (m1 - m2) / (m1 + m2) * 10.0, e2 = 2.0 * m1 / (m1 + m2) * 10.0;
    return std::max(std::fabs(v1_ - e1), std::fabs(v2_ - e2)) / 10.0;
  }

 private:
  float m2_;
  double v1_ = 0, v2_ = 0;
};

/// D. Newton's cradle: five touching spheres at rest, a sixth arrives at 1 m/s along the row,
/// e = 1, no gravity: only the far sphere leaves, at 1 m/s. Error: the worst velocity off.
class Cradle final : public AccuracyCase {
 public:
  std::string name() const override { return "D-cradle"; }
  std::string summary() const override { return "six spheres, e = 1: only the far one leaves, at 1 m/s"; }
  PeerScene scene() const override {
    PeerScene s;
    s.name = name();
    s.gravity = Vec3(0, 0, 0);
    s.spheres.push_back(
        {.position = {-1.5f, 0, 0}, .velocity = {1, 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 1, .friction = 0});
    for (int k = 0; k < 5; ++k)
      s.spheres.push_back({.position = {float(k), 0, 0}, .radius = 0.5f, .mass = 1, .restitution = 1, .friction = 0});
    return s;
  }
  double duration() const override { return 2.0; }
  void reset() override { v_.assign(6, 0.0); }
  void observe(const std::vector<PeerState>& state, double) override {
    for (std::size_t k = 0; k < 6; ++k) v_[k] = state[k].velocity.x();
  }
  double error() const override {
    double worst = 0.0;
    for (std::size_t k = 0; k < 6; ++k) worst = std::max(worst, std::fabs(v_[k] - (k == 5 ? 1.0 : 0.0)));
    return worst;
  }

 private:
  std::vector<double> v_ = std::vector<double>(6, 0.0);
};

/// Slope roll: a solid sphere released on a 20-degree plane with mu 0.5 rolls without slipping
/// at a = 5/7 g sin(theta); the error is that of a = 2 s / t^2 after 1 s.
class SlopeRoll final : public AccuracyCase {
 public:
  std::string name() const override { return "slope-roll"; }
  std::string summary() const override { return "rolling down 20 degrees, mu 0.5: a = 5/7 g sin(theta)"; }
  PeerScene scene() const override {
    PeerScene s;
    s.name = name();
    const float c = std::cos(kTheta), sn = std::sin(kTheta);
    s.planes.push_back({.normal = {sn, c, 0}, .offset = 0, .restitution = 0.0f, .friction = 0.5f});
    s.spheres.push_back(
        {.position = {0.5f * sn, 0.5f * c, 0}, .radius = 0.5f, .mass = 1, .restitution = 0.0f, .friction = 0.5f});
    return s;
  }
  double duration() const override { return 1.0; }
  void reset() override { travelled_ = 0.0, t_ = 0.0; }
  void observe(const std::vector<PeerState>& state, double t) override {
    const double c = std::cos(kTheta), sn = std::sin(kTheta);
    const double dx = state[0].position.x() - 0.5 * sn, dy = state[0].position.y() - 0.5 * c;
    travelled_ = dx * c - dy * sn, t_ = t;  // along (cos, -sin, 0), downhill
  }
  double error() const override {
    const double exact = 5.0 / 7.0 * kG * std::sin(kTheta);
    return std::fabs(2.0 * travelled_ / (t_ * t_) - exact) / exact;
  }

 private:
  static constexpr float kTheta = 0.34906585f;  // 20 degrees
  double travelled_ = 0.0, t_ = 0.0;
};

}  // namespace

std::vector<std::unique_ptr<AccuracyCase>> known_answer_cases() {
  std::vector<std::unique_ptr<AccuracyCase>> cases;
  cases.push_back(std::make_unique<Bounce>(false));
  cases.push_back(std::make_unique<Bounce>(true));
  cases.push_back(std::make_unique<SlideToRoll>());
  cases.push_back(std::make_unique<HeadOn>(1.0f));
  cases.push_back(std::make_unique<HeadOn>(1000.0f));
  cases.push_back(std::make_unique<Cradle>());
  cases.push_back(std::make_unique<SlopeRoll>());
  return cases;
}

}  // namespace hail::bench

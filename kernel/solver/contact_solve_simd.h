#pragma once
// The collision and resting passes of kernel/solver/contact_impulse.h, a batch of contacts per
// instruction (4 under SSE4.2, 8 under AVX2, 16 under AVX-512: the active SIMD path of
// kernel/dispatch/simd_dispatch.h), over contacts that share no sphere (one colour).
//
// Once per step ContactBatches::stage copies each colour's contacts into SoA batches: normal,
// gap, material, the bodies' slots and mass properties, and the accumulated impulses. A pass
// then only gathers the bodies' velocities (from the 64-byte SolverBody lines), runs the rule
// on all lanes and scatters the velocities back; what never changes within a step is not
// re-read from the contacts on every pass. A colour's last batch is filled up with padding
// lanes (both sides the static body: zero inverse masses, so every rule leaves them inactive),
// so small colours (the solver's tiles have many) run in SIMD too; only a serial overflow
// colour stays with the scalar rules. The passes themselves are in
// kernel/simd/contact_solve.cpp, compiled once per SIMD path.
//
// Each lane performs the scalar rule's float operations in the scalar rule's order, and a lane
// the scalar code would skip (an early return) keeps its values through a select, so the result
// is bitwise the scalar result: the scalar functions stay the reference, and
// tests/test_contact_solve_simd.cpp and tests/test_simd_dispatch.cpp compare the two on random
// contacts. Since the contacts of a colour share no sphere, how they fall into batches changes
// nothing either: the result does not depend on W.

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "hail/aligned_array.h"
#include "hail/contact.h"
#include "kernel/solver/contact_impulse.h"
#include "kernel/solver/depenetrate.h"
#include "kernel/solver/soft_contact.h"
#include "kernel/solver/solver_body.h"
#include "soa/heap_bytes.h"

namespace hail {

struct SimdKernels;

/// Contacts per SIMD batch on the active SIMD path (kernel/dispatch/simd_dispatch.h).
std::size_t contact_batch_width();

/// The staged batches as plain arrays, lane k * width + l for lane l of batch k: what the SIMD
/// passes (kernel/simd/contact_solve.cpp) read, and the impulses they accumulate.
struct ContactBatchArrays {
  std::size_t width;
  const std::int32_t *a, *b;  ///< body slots (b: the static body for static contacts)
  const float *nx, *ny, *nz, *gap, *restitution, *friction;
  const float *ra, *rb;  ///< radii (rb 0 for static contacts)
  float *normal_impulse, *tx, *ty, *tz;
  float* bounce_impulse;   ///< the collision passes' normal impulses, summed (Contact::bounce_impulse)
  const float* surface_d;  ///< Contact::surface_d (the depenetration pass's static gap)
  /// Per batch: 1 when every lane's b is the static body. Such a batch (terrain and plane
  /// contacts come first in each colour, so most of them fill whole batches) loads and stores
  /// only its a side: b's velocity and inverse mass are zero, as the static body's are.
  const std::uint8_t* static_b;
};

class ContactBatches {
 public:
  /// Stages contacts[colour_begin[c] .. colour_begin[c+1]) for the colours c < batched_colours
  /// (each must share no sphere) in batches, the last one padded; later colours are left to
  /// the scalar rules. `bodies` must end with one static body (zero velocity and
  /// inverse mass), whose slot static contacts gather from. Allocates only on growth.
  void stage(std::span<const Contact> contacts, std::span<const std::uint32_t> colour_begin,
             std::size_t batched_colours, std::span<const SolverBody> bodies);
  /// stage() in two parts, so that the copying can run in parallel: plan() lays out the
  /// batches (serial, cheap), fill() copies batches [first, last) (disjoint ranges in parallel).
  /// Colour c is batched unless serial[c] is non-zero (its contacts may share spheres: all of
  /// them are left to the scalar rules, as its "tail"). plan() takes the active SIMD path's
  /// width and kernels; the passes until the next plan() use those, whatever path is made
  /// active meanwhile.
  void plan(std::span<const std::uint32_t> colour_begin, std::span<const std::uint8_t> serial);
  void fill(std::size_t first, std::size_t last, std::span<const Contact> contacts, std::span<const SolverBody> bodies);
  /// fill() with the spheres' radii by slot (`radius`, the values the bodies hold) instead of
  /// the bodies, whose static body has slot radius.size(): the step's solve reads 4 bytes a
  /// sphere instead of a 64-byte body line (the radius loads were much of fill's time in large
  /// worlds: docs/benchmarks.md, "Figures behind the code's choices").
  void fill(std::size_t first, std::size_t last, std::span<const Contact> contacts, std::span<const float> radius);
  [[nodiscard]] std::size_t batch_count() const { return first_contact_.size(); }
  /// Contacts per batch, as the last plan() laid them out.
  [[nodiscard]] std::size_t width() const { return width_; }

  /// Batches of colour c: [batch_begin(c), batch_end(c)). Its scalar tail is contacts
  /// [tail_begin(c), colour_begin[c + 1]): empty for a batched colour, all of a serial one.
  [[nodiscard]] std::size_t batch_begin(std::size_t c) const { return colour_batches_[c]; }
  [[nodiscard]] std::size_t batch_end(std::size_t c) const { return colour_batches_[c + 1]; }
  [[nodiscard]] std::size_t tail_begin(std::size_t c) const { return tail_begin_[c]; }
  /// The contacts of batches [first, last) (of one colour): [first index, end index).
  [[nodiscard]] std::pair<std::size_t, std::size_t> contact_range(std::size_t first, std::size_t last) const {
    if (first >= last) return {0, 0};
    return {first_contact_[first], first_contact_[last - 1] + batch_lanes_[last - 1]};
  }

  /// Collision pass number `pass` (0, 1, ...) (solve_collision) over batches [first, last);
  /// true when any lane applied an impulse. Batches of one colour may run in parallel. From
  /// pass 1 on, a batch none of whose bodies changed since the previous pass began is skipped:
  /// none of its contacts applied then, so none can now (SolverBody::changed_in_pass); the
  /// result is the same as evaluating it. `gravity_dt` (g dt; Integrator::UniformAcceleration,
  /// else null): restitution from the approach speed (solve_collision's gravity_closing).
  bool solve_collision(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float dt,
                       float restitution_threshold, std::uint32_t pass, FrictionWork work = kWithFriction,
                       const float* gravity_dt = nullptr);
  /// Warm start (apply_warm_start) of batches [first, last): their staged impulses applied.
  void warm_start(std::size_t first, std::size_t last, std::span<SolverBody> bodies, FrictionWork work = kWithFriction);
  /// Resting pass (solve_resting) over batches [first, last).
  void solve_resting(std::size_t first, std::size_t last, std::span<SolverBody> bodies, float inv_dt,
                     FrictionWork work = kWithFriction);
  /// One pass of the soft step (Solver::SoftStep: soft_run_scalar's rules, kernel/solver/soft_step.h)
  /// over batches [first, last) of one colour; batches of one colour may run in parallel.
  void solve_soft(std::size_t first, std::size_t last, std::span<SolverBody> bodies, const SoftPass& pass,
                  FrictionWork work = kWithFriction);
  /// One depenetration pass (push_apart, kernel/solver/depenetrate.h) over batches [first, last) of
  /// one colour, numbered `now` (StepPipeline::depenetrate): a contact neither of whose spheres
  /// moved since `previous` (moved[slot] < previous; 0 in the first pass: none skipped) is
  /// skipped; a contact that pushes sets both spheres' moved to `now`. Batches of one colour may
  /// run in parallel. The positions are those of the spheres staged (the slots of the last
  /// fill), bitwise as the scalar loop over the same contacts moves them. True if a contact
  /// pushed from an overlap beyond twice the slop (push_apart's deep flag).
  bool depenetrate(std::size_t first, std::size_t last, const DepenetrationArrays& spheres, std::uint32_t now,
                   std::uint32_t previous);
  /// Writes the batches' accumulated impulses (resting, friction and bounce) back to the
  /// contacts they were staged from.
  void store_impulses(std::span<Contact> contacts) const;
  /// store_impulses of batches [first, last): disjoint ranges may run in parallel.
  void store_impulses(std::span<Contact> contacts, std::size_t first, std::size_t last) const;

  /// Heap bytes held (capacities), for World::memory_use.
  [[nodiscard]] std::size_t heap_bytes() const {
    return heap_bytes_of(colour_batches_, tail_begin_, first_contact_, batch_lanes_, a_, b_, static_b_, stage_serial_, nx_, ny_, nz_, gap_, restitution_, friction_, ra_, rb_, surface_d_, normal_impulse_, tx_, ty_, tz_, bounce_impulse_);
  }

 private:
  [[nodiscard]] ContactBatchArrays arrays();
  template <class RadiusOf>
  void fill_batches(std::size_t first, std::size_t last, std::span<const Contact> contacts, std::int32_t static_slot,
                    RadiusOf&& radius_of);
  const SimdKernels* kernels_ = nullptr;  // of the last plan()
  std::size_t width_ = 1;
  std::vector<std::size_t> colour_batches_, tail_begin_;
  std::vector<std::uint32_t> first_contact_;  // per batch: index of its lane-0 contact
  std::vector<std::uint8_t> batch_lanes_;     // per batch: its contacts (W, or fewer in a colour's last batch)
  AlignedArray<std::int32_t> a_, b_;          // body slots (b: the static body for static contacts)
  std::vector<std::uint8_t> static_b_;        // per batch: every lane's b is the static body
  std::vector<std::uint8_t> stage_serial_;    // stage()'s per-colour flags for plan()
  AlignedArray<float> nx_, ny_, nz_, gap_, restitution_, friction_;
  AlignedArray<float> ra_, rb_, surface_d_;
  AlignedArray<float> normal_impulse_, tx_, ty_, tz_, bounce_impulse_;
};

/// The scalar rules over a run of contacts: the reference, and the path for a serial overflow
/// colour (whose contacts may share spheres).
/// `pass` marks the bodies it changes (SolverBody::changed_in_pass = pass + 1); it evaluates
/// every contact. `work` (kernel/solver/contact_impulse.h): kNoFriction when no contact has friction
/// (no friction and no angular work), kLinearFriction without rotation (friction on linear
/// velocities; angular velocities neither read nor written), kWithFriction the full rules; the
/// same holds for ContactBatches, bit for bit.
bool solve_collision_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float dt,
                                float restitution_threshold, std::uint32_t pass = 0, FrictionWork work = kWithFriction,
                                const float* gravity_dt = nullptr);
void solve_resting_run_scalar(std::span<Contact> contacts, std::span<SolverBody> bodies, float inv_dt,
                              FrictionWork work = kWithFriction);
void warm_start_run_scalar(std::span<const Contact> contacts, std::span<SolverBody> bodies,
                           FrictionWork work = kWithFriction);

}  // namespace hail

#include "hail/sphere_soa.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "hail/errors.h"

namespace hail {
namespace {
constexpr std::uint32_t kFreeSlot = 0xFFFFFFFFu;
const SphereRecord kPaddingRecord{kPaddingPosition,
                                  kPaddingPosition,
                                  kPaddingPosition,
                                  0,
                                  0,
                                  0,
                                  0,
                                  0,
                                  0,
                                  0.0f,
                                  0.0f,
                                  0.0f,
                                  0.0f,
                                  0.0f,
                                  kSphereFlagNone,
                                  0.0f,
                                  {0.0f, 0.0f, 0.0f},
                                  {0.0f, 0.0f, 0.0f},
                                  0,
                                  CollisionFilter{0, 0},
                                  0.0f,
                                  0};
}  // namespace

// Every per-sphere array is in for_each_array: a member added to SphereSoA (or a field to
// SphereRecord) without it fails here, so that nothing sizes, re-sorts or saves all but it.
static_assert(sizeof(SphereSoA) == (SphereSoA::kArrayCount + 3) * sizeof(AlignedArray<float>) + sizeof(std::size_t) +
                                       5 * sizeof(std::vector<std::uint32_t>),
              "a SphereSoA member was added: list a per-sphere array in SphereSoA::for_each_array (and raise "
              "kArrayCount), and bump kSnapshotVersion (include/hail/snapshot.h)");
static_assert(sizeof(SphereRecord) == 16 * 4 + 6 * 4 + 8 + sizeof(CollisionFilter) + 2 * 4,
              "a SphereRecord field was added: give it a SphereSoA array in for_each_array");

void SphereSoA::resize_arrays(std::size_t n) {
  for_each_array([n](const char*, auto& a) { a.resize(n); });
}

void SphereSoA::reserve(std::size_t n) {
  if (n > kMaxSpheres)
    throw InvalidArgument("hail: cannot reserve room for " + std::to_string(n) + " spheres: at most " +
                          std::to_string(kMaxSpheres) + " (a handle index is 32 bits)");
  const std::size_t padded = padded_size_for(n);
  for_each_array([padded](const char*, auto& a) { a.reserve(padded); });
  slot_ids_.reserve(n);
  id_to_slot_.reserve(n);
  generation_.reserve(n);
}

void SphereSoA::reserve_like(const SphereSoA& other) {
  const std::size_t padded = other.padded_size();
  for_each_array([padded](const char*, auto& a) { a.reserve(padded); });
  slot_ids_.reserve(other.slot_ids_.size());
  id_to_slot_.reserve(other.id_to_slot_.size());
  generation_.reserve(other.generation_.size());
  free_ids_.reserve(other.free_ids_.size());
}

void SphereSoA::assign(const SphereSoA& other) noexcept {
  auto copy = [](const char*, auto& mine, const auto& theirs) {
    mine.resize(theirs.size());  // within capacity: no allocation
    if (theirs.size()) std::memcpy(mine.data(), theirs.data(), theirs.size() * sizeof theirs[0]);
  };
  for_each_array_of(copy, *this, other);
  // Vector copy-assignment reuses the storage when it is large enough (reserve_like made it so).
  slot_ids_ = other.slot_ids_;
  id_to_slot_ = other.id_to_slot_;
  generation_ = other.generation_;
  free_ids_ = other.free_ids_;
  size_ = other.size_;
}

void SphereSoA::restore_handles(std::span<const SphereId> handles, std::span<const std::uint32_t> generations,
                                std::span<const std::uint32_t> free_indices) {
  auto refuse = [](const std::string& what) { throw InvalidArgument("hail: sphere handles: " + what); };
  const std::size_t indices = generations.size();
  if (indices >= kFreeSlot) refuse(std::to_string(indices) + " handle indices, more than a SphereId can name");
  if (handles.size() + free_indices.size() != indices)
    refuse(std::to_string(handles.size()) + " live and " + std::to_string(free_indices.size()) +
           " free handle indices, but " + std::to_string(indices) + " indices issued");
  std::vector<std::uint32_t> id_to_slot(indices, kFreeSlot);
  std::vector<std::uint8_t> seen(indices, 0);
  for (std::size_t k = 0; k < handles.size(); ++k) {
    const SphereId id = handles[k];
    if (id.index >= indices || seen[id.index])
      refuse("slot " + std::to_string(k) + "'s handle index " + std::to_string(id.index) +
             (id.index >= indices ? " is out of range" : " is used twice"));
    if (id.generation != generations[id.index])
      refuse("slot " + std::to_string(k) + "'s handle " + std::to_string(id.index) + "/" +
             std::to_string(id.generation) + " is not its index's generation " + std::to_string(generations[id.index]));
    seen[id.index] = 1;
    id_to_slot[id.index] = static_cast<std::uint32_t>(k);
  }
  for (std::uint32_t index : free_indices) {
    if (index >= indices || seen[index])
      refuse("free index " + std::to_string(index) +
             (index >= indices ? " is out of range" : " is live or listed twice"));
    seen[index] = 1;
  }
  size_ = 0;
  set_padding(handles.size());
  size_ = handles.size();
  slot_ids_.assign(handles.begin(), handles.end());
  id_to_slot_ = std::move(id_to_slot);
  generation_.assign(generations.begin(), generations.end());
  free_ids_.assign(free_indices.begin(), free_indices.end());
}

void SphereSoA::write_slot(std::size_t s, const SphereRecord& r) {
  px[s] = r.px;
  py[s] = r.py;
  pz[s] = r.pz;
  vx[s] = r.vx;
  vy[s] = r.vy;
  vz[s] = r.vz;
  wx[s] = r.wx;
  wy[s] = r.wy;
  wz[s] = r.wz;
  radius[s] = r.radius;
  inv_mass[s] = r.inv_mass;
  inv_inertia[s] = r.inv_inertia;
  restitution[s] = r.restitution;
  friction[s] = r.friction;
  flags[s] = r.flags;
  gravity_scale[s] = r.gravity_scale;
  force_x[s] = r.force[0], force_y[s] = r.force[1], force_z[s] = r.force[2];
  torque_x[s] = r.torque[0], torque_y[s] = r.torque[1], torque_z[s] = r.torque[2];
  user_data[s] = r.user_data;
  collision_category[s] = r.filter.category;
  collision_mask[s] = r.filter.mask;
  sleep_timer[s] = r.sleep_timer;
  sleep_island[s] = r.sleep_island;
}

SphereRecord SphereSoA::read_slot(std::size_t s) const {
  return {px[s],
          py[s],
          pz[s],
          vx[s],
          vy[s],
          vz[s],
          wx[s],
          wy[s],
          wz[s],
          radius[s],
          inv_mass[s],
          inv_inertia[s],
          restitution[s],
          friction[s],
          flags[s],
          gravity_scale[s],
          {force_x[s], force_y[s], force_z[s]},
          {torque_x[s], torque_y[s], torque_z[s]},
          user_data[s],
          {collision_category[s], collision_mask[s]},
          sleep_timer[s],
          sleep_island[s]};
}

void SphereSoA::set_padding(std::size_t first) {
  const std::size_t padded = padded_size_for(first);
  resize_arrays(padded);
  for (std::size_t s = first; s < padded; ++s) write_slot(s, kPaddingRecord);
}

SphereId SphereSoA::add(const SphereRecord& record) {
  const bool fresh_index = free_ids_.empty();
  if (fresh_index && id_to_slot_.size() >= kMaxSpheres)
    throw InvalidArgument("hail: cannot add a sphere: all " + std::to_string(kMaxSpheres) +
                          " handle indices are in use");
  // Everything that can throw (std::bad_alloc) comes first and is undone on the way out, so a
  // failed add leaves no index that is neither live nor free (a snapshot would refuse that).
  set_padding(size_ + 1);  // the new slot is a padding lane until written below
  const std::uint32_t id = fresh_index ? static_cast<std::uint32_t>(id_to_slot_.size()) : free_ids_.back();
  slot_ids_.push_back({id, fresh_index ? 0u : generation_[id]});
  if (fresh_index) {
    try {
      id_to_slot_.push_back(kFreeSlot);
      generation_.push_back(0);
    } catch (...) {
      slot_ids_.pop_back();
      if (id_to_slot_.size() > id) id_to_slot_.pop_back();
      throw;
    }
  } else {
    free_ids_.pop_back();
  }
  const std::size_t slot = size_;
  write_slot(slot, record);
  ++size_;
  id_to_slot_[id] = static_cast<std::uint32_t>(slot);
  return {id, generation_[id]};
}

std::int64_t SphereSoA::slot_of(SphereId id) const noexcept {
  if (id.index >= id_to_slot_.size() || generation_[id.index] != id.generation) return -1;
  const std::uint32_t slot = id_to_slot_[id.index];
  return slot == kFreeSlot ? -1 : static_cast<std::int64_t>(slot);
}

std::int64_t SphereSoA::slot_of_index(std::uint32_t index) const noexcept {
  if (index >= id_to_slot_.size()) return -1;
  const std::uint32_t slot = id_to_slot_[index];
  return slot == kFreeSlot ? -1 : static_cast<std::int64_t>(slot);
}

bool SphereSoA::remove(SphereId id) {
  const std::int64_t found = slot_of(id);
  if (found < 0) return false;
  const std::size_t slot = static_cast<std::size_t>(found);
  const std::size_t last = size_ - 1;
  if (slot != last) {
    write_slot(slot, read_slot(last));
    slot_ids_[slot] = slot_ids_[last];
    id_to_slot_[slot_ids_[slot].index] = static_cast<std::uint32_t>(slot);
  }
  slot_ids_.pop_back();
  id_to_slot_[id.index] = kFreeSlot;
  ++generation_[id.index];
  free_ids_.push_back(id.index);
  --size_;
  set_padding(size_);
  return true;
}

void SphereSoA::permute(std::span<const std::uint32_t> order, bool angular, bool accumulators) {
  permute(order, angular, accumulators, [](std::size_t count, auto&& f) { f(std::size_t{0}, count); });
}

}  // namespace hail

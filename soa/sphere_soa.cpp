#include "hail/sphere_soa.h"

#include <algorithm>

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
                                  CollisionFilter{0, 0}};
}  // namespace

void SphereSoA::resize_arrays(std::size_t n) {
  for (auto* a : {&px,       &py,          &pz,          &vx,       &vy,
                  &vz,       &wx,          &wy,          &wz,       &radius,
                  &inv_mass, &inv_inertia, &restitution, &friction, &gravity_scale,
                  &force_x,  &force_y,     &force_z,     &torque_x, &torque_y,
                  &torque_z})
    a->resize(n);
  for (auto* a : {&flags, &collision_category, &collision_mask}) a->resize(n);
  user_data.resize(n);
}

void SphereSoA::reserve(std::size_t n) {
  const std::size_t padded = padded_size_for(n);
  for (auto* a : {&px,       &py,          &pz,          &vx,       &vy,
                  &vz,       &wx,          &wy,          &wz,       &radius,
                  &inv_mass, &inv_inertia, &restitution, &friction, &gravity_scale,
                  &force_x,  &force_y,     &force_z,     &torque_x, &torque_y,
                  &torque_z})
    a->reserve(padded);
  for (auto* a : {&flags, &collision_category, &collision_mask}) a->reserve(padded);
  user_data.reserve(padded);
  slot_ids_.reserve(n);
  id_to_slot_.reserve(n);
  generation_.reserve(n);
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
          {collision_category[s], collision_mask[s]}};
}

void SphereSoA::set_padding(std::size_t first) {
  const std::size_t padded = padded_size_for(first);
  resize_arrays(padded);
  for (std::size_t s = first; s < padded; ++s) write_slot(s, kPaddingRecord);
}

SphereId SphereSoA::add(const SphereRecord& record) {
  std::uint32_t id;
  if (!free_ids_.empty()) {
    id = free_ids_.back();
    free_ids_.pop_back();
  } else {
    id = static_cast<std::uint32_t>(id_to_slot_.size());
    id_to_slot_.push_back(kFreeSlot);
    generation_.push_back(0);
  }
  const std::size_t slot = size_;
  set_padding(size_ + 1);
  write_slot(slot, record);
  ++size_;
  slot_ids_.push_back({id, generation_[id]});
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

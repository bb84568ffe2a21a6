#include "hail/sphere_soa.h"

#include <algorithm>

namespace hail {
namespace {
constexpr std::uint32_t kFreeSlot = 0xFFFFFFFFu;
const SphereRecord kPaddingRecord{
    kPaddingPosition, kPaddingPosition, kPaddingPosition, 0, 0, 0, 0, 0, 0, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f,
    kSphereFlagNone};
}  // namespace

void SphereSoA::resize_arrays(std::size_t n) {
  for (auto* a :
       {&px, &py, &pz, &vx, &vy, &vz, &wx, &wy, &wz, &radius, &inv_mass, &inv_inertia, &restitution, &friction})
    a->resize(n);
  flags.resize(n);
}

void SphereSoA::reserve(std::size_t n) {
  const std::size_t padded = padded_size_for(n);
  for (auto* a :
       {&px, &py, &pz, &vx, &vy, &vz, &wx, &wy, &wz, &radius, &inv_mass, &inv_inertia, &restitution, &friction})
    a->reserve(padded);
  flags.reserve(padded);
  slot_to_id_.reserve(n);
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
}

SphereRecord SphereSoA::read_slot(std::size_t s) const {
  return {px[s], py[s],     pz[s],       vx[s],          vy[s],          vz[s],       wx[s],   wy[s],
          wz[s], radius[s], inv_mass[s], inv_inertia[s], restitution[s], friction[s], flags[s]};
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
  slot_to_id_.push_back(id);
  id_to_slot_[id] = static_cast<std::uint32_t>(slot);
  return {id, generation_[id]};
}

std::int64_t SphereSoA::slot_of(SphereId id) const noexcept {
  if (id.index >= id_to_slot_.size() || generation_[id.index] != id.generation) return -1;
  const std::uint32_t slot = id_to_slot_[id.index];
  return slot == kFreeSlot ? -1 : static_cast<std::int64_t>(slot);
}

bool SphereSoA::remove(SphereId id) {
  const std::int64_t found = slot_of(id);
  if (found < 0) return false;
  const std::size_t slot = static_cast<std::size_t>(found);
  const std::size_t last = size_ - 1;
  if (slot != last) {
    write_slot(slot, read_slot(last));
    slot_to_id_[slot] = slot_to_id_[last];
    id_to_slot_[slot_to_id_[slot]] = static_cast<std::uint32_t>(slot);
  }
  slot_to_id_.pop_back();
  id_to_slot_[id.index] = kFreeSlot;
  ++generation_[id.index];
  free_ids_.push_back(id.index);
  --size_;
  set_padding(size_);
  return true;
}

void SphereSoA::permute(std::span<const std::uint32_t> order, bool angular) {
  permute(order, angular, [](std::size_t count, auto&& f) { f(std::size_t{0}, count); });
}

}  // namespace hail

// World::memory_use: the heap bytes of the World's buffers, by part, from their capacities.

#include "hail/world.h"
#include "kernel/world/step_scratch.h"
#include "kernel/world/world_services.h"
#include "soa/heap_bytes.h"

namespace hail {

MemoryUse World::memory_use() const {
  const StepScratch& st = *scratch_;
  const WorldServices& sv = *services_;
  MemoryUse m;
  m.spheres = spheres_.heap_bytes();
  m.pairs = heap_bytes_of(st.pair_blocks, st.pair_row_scratch) + st.grid.heap_bytes() + st.sorted_axis.heap_bytes() +
            st.sphere_bvh.heap_bytes();
  m.contacts = heap_bytes_of(st.contact_blocks, st.contacts, st.coloured_contacts, st.impact_blocks, st.impacts,
                             st.merge_offsets);
  m.solver = st.colouring.heap_bytes() + heap_bytes_of(st.tile_changed, st.solver_bodies) +
             st.contact_batches.heap_bytes() + st.shock.heap_bytes() + st.bounce_timing.heap_bytes() +
             heap_bytes_of(st.rolling_impulses);
  m.warm_start = st.contact_cache.heap_bytes();
  m.sweep = st.ccd.heap_bytes() + heap_bytes_of(st.fast_blocks, st.fast, st.block_max_speed, st.block_extremes);
  m.per_sphere = heap_bytes_of(st.start_x, st.start_y, st.start_z, st.reach2, st.start_vx, st.start_vy, st.start_vz,
                               st.travel, st.moved_at, st.reorder_keys, st.reorder_slots, st.reorder_bounds);
  m.services = sv.events.heap_bytes() + sv.sleep.heap_bytes() + sv.sphere_queries.heap_bytes() +
               heap_bytes_of(sv.impulse_undo);
  return m;
}

}  // namespace hail

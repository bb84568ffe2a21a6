# hail.World from Python: settings as keywords, exceptions, spheres, stepping, views, snapshots,
# events, queries and terrain.
import threading
import time

import numpy as np
import pytest

import hail


def pile(threads=1, n=200, seed=1, **settings):
    """n spheres dropped on a plane, from a fixed seed."""
    world = hail.World(threads=threads, **settings)
    world.add_plane((0, 1, 0), 0.0)
    rng = np.random.default_rng(seed)
    positions = rng.uniform((0, 1, 0), (6, 8, 6), size=(n, 3))
    handles = world.add_spheres(positions, radii=rng.uniform(0.1, 0.3, n), masses=1.0)
    return world, handles


def test_settings_are_keywords_and_read_back():
    world = hail.World(threads=1, sleep=True, pair_search="grid", soft_step_substeps=6, gravity=(0, -5, 0))
    s = world.settings
    assert s["sleep"] is True and s["pair_search"] == "grid" and s["soft_step_substeps"] == 6
    assert s["gravity"] == pytest.approx((0, -5, 0))
    assert hail.World(soft_step={"substeps": 7}).settings["soft_step_substeps"] == 7


def test_every_table_setting_is_a_keyword():
    table = hail.settings_table()
    names = {row["name"] for row in table}
    assert names == set(hail.World().settings)
    assert {"threads", "soft_step_substeps", "pair_search", "gravity"} <= names
    for row in table:  # each default passes back in as its own keyword
        hail.World(**{row["name"]: row["default"]})
    assert "soft_step_substeps" in hail.World.__init__.__doc__


@pytest.mark.parametrize(
    "kwargs, exception, named",
    [
        ({"time_scale": -1.0}, hail.InvalidArgument, "-1"),
        ({"threads": 99999}, hail.InvalidArgument, "99999"),
        ({"threads": 2**70}, hail.InvalidArgument, str(2**70)),
        ({"pair_search": "fastest"}, hail.InvalidArgument, "fastest"),
        ({"soft_step_contact_cycles": 0.5}, hail.InvalidArgument, "0.5"),
        ({"max_substep": 1e300}, hail.InvalidArgument, "1e+300"),
        ({"sleep": 1}, TypeError, "sleep"),
        ({"gravity": (0, 1)}, TypeError, "gravity"),
        ({"threads": 1.5}, TypeError, "1.5"),
        ({"no_such_setting": 1}, TypeError, "no_such_setting"),
    ],
)
def test_bad_settings_raise_naming_the_value(kwargs, exception, named):
    with pytest.raises(exception) as info:
        hail.World(**kwargs)
    assert named in str(info.value)


def test_exception_types():
    assert issubclass(hail.InvalidArgument, ValueError)
    assert issubclass(hail.FileError, OSError)
    assert issubclass(hail.SizeLimitError, hail.FileError)


def test_bad_values_change_nothing():
    world, handles = pile()
    world.step(1 / 60, n=5)
    before = world.save()
    h = int(handles[3])
    for call in (
        lambda: world.set_restitution(h, 2.0),
        lambda: world.set_radius(h, -1.0),
        lambda: world.set_velocity(h, (np.nan, 0, 0)),
        lambda: world.add_sphere((0, 1, 0), radius=0.0),
        lambda: world.add_spheres([[0, 1, 0], [1, 1, 0], [2, 1, 0]], radii=[0.2, 0.2, -0.2]),
        lambda: world.step(-1.0),
        lambda: world.set_positions(handles[:2], [[0, 1, 0], [np.inf, 0, 0]]),
    ):
        with pytest.raises(hail.InvalidArgument):
            call()
        assert world.save() == before
    with pytest.raises(hail.InvalidArgument, match="sphere 2"):
        world.add_spheres([[0, 1, 0], [1, 1, 0], [2, 1, 0]], radii=[0.2, 0.2, -0.2])
    assert len(world) == len(handles)


def test_stale_handle_raises():
    world, handles = pile(n=3)
    h = int(handles[0])
    assert world.remove_sphere(h)
    assert not world.remove_sphere(h)
    with pytest.raises(hail.InvalidArgument):
        world.position(h)
    assert world.slot_of(h) == -1


def test_views_match_the_world_and_refuse_writes():
    world, handles = pile(n=300)
    world.step(1 / 60, n=40)  # past a Morton re-sort: slots no longer follow the handles
    px, py, pz, radii, ids = world.px, world.py, world.pz, world.radii, world.handles
    assert px.shape == (300,) and px.dtype == np.float32 and ids.dtype == np.uint64
    for h in handles[::7]:
        slot = world.slot_of(int(h))
        assert ids[slot] == h
        assert (px[slot], py[slot], pz[slot]) == tuple(world.position(int(h)))
        assert world.velocities[slot].tolist() == world.velocity(int(h)).tolist()
    np.testing.assert_array_equal(world.positions, np.stack([px, py, pz], axis=1))
    for view in (px, radii, ids, world.vx, world.flags):
        assert not view.flags.writeable
        with pytest.raises(ValueError):
            view[0] = 1
    # No copy: the view sees the next step, and keeps the World alive.
    y0 = py.copy()
    world.step(1 / 60)
    assert not np.array_equal(py, y0)
    np.testing.assert_array_equal(py, world.positions[:, 1])
    assert py.base is not None
    del world
    assert np.isfinite(py).all()


def test_snapshots_round_trip_bitwise():
    world, _ = pile(n=150, sleep=True)
    world.step(1 / 60, n=30)
    snapshot = world.save()
    assert isinstance(snapshot, bytes)
    world.step(1 / 60, n=45)
    expected = world.state_hash(), world.save()
    world.restore(snapshot)
    world.step(1 / 60, n=45)
    assert (world.state_hash(), world.save()) == expected
    other = hail.World(threads=2)
    other.add_plane((0, 1, 0), 0.0)
    other.restore(snapshot)
    other.step(1 / 60, n=45)
    assert other.state_hash() == expected[0]
    with pytest.raises(hail.InvalidArgument):
        world.restore(snapshot[: len(snapshot) // 2])
    assert world.save() == expected[1]


def test_snapshot_files(tmp_path):
    world, _ = pile(n=20)
    world.save_file(str(tmp_path / "w.snap"))
    copy = hail.World()
    copy.restore_file(str(tmp_path / "w.snap"))
    assert copy.state_hash() == world.state_hash()
    with pytest.raises(hail.FileError, match="missing.snap"):
        copy.restore_file(str(tmp_path / "missing.snap"))


def test_same_hash_on_any_thread_count():
    hashes = set()
    for threads in (1, 2, 3):
        world, _ = pile(threads=threads, n=400)
        world.step(1 / 60, n=60)
        hashes.add(world.state_hash())
    assert len(hashes) == 1


def test_memory_use_by_part():
    world, handles = pile(n=300)
    world.step(1 / 60, n=90)
    m = world.memory_use()
    parts = ("spheres", "pairs", "contacts", "solver", "warm_start", "sweep", "per_sphere", "services")
    assert m["total"] == sum(m[p] for p in parts)
    assert m["spheres"] >= 300 * 9 * 4  # positions, velocities and spins: nine floats a sphere
    assert m["contacts"] > 0 and m["solver"] > 0


def test_control_calls():
    world = hail.World(threads=1, gravity=(0, 0, 0))
    h = world.add_sphere((0, 1, 0), radius=0.5, mass=2.0)
    world.apply_impulse(h, (2, 0, 0))
    assert world.velocity(h).tolist() == [1, 0, 0]
    world.apply_force(h, (0, 0, 120))
    world.step(1 / 60)
    assert world.velocity(h)[2] == pytest.approx(1.0)
    world.set_user_data(h, 42)
    assert world.user_data(h) == 42 and world.user_data_values[world.slot_of(h)] == 42
    world.set_collision_filter(h, 2, 0xFF)
    assert world.collision_filter(h) == (2, 0xFF)
    k = world.add_sphere((5, 1, 0), is_kinematic=True)
    world.move_kinematic(k, (6, 1, 0), 1 / 60)
    world.step(1 / 60)
    assert world.position(k)[0] == pytest.approx(6.0)
    world.set_dynamic(k, 3.0)
    assert not world.is_kinematic(k)
    stats, times = world.last_step_stats(), world.last_phase_times()
    assert "sphere_contacts" in stats and times["total"] >= 0


def test_events_are_structured_arrays():
    world = hail.World(threads=1)
    world.add_plane((0, 1, 0), 0.0)
    a = world.add_sphere((0, 0.6, 0), radius=0.5, velocity=(0, -4, 0))
    world.set_events(touch=True, hits=True, hit_speed=1.0)
    begun, hits = [], []
    for _ in range(30):
        world.step(1 / 60)
        begun.extend(world.touch_begin_events.tolist())
        hits.extend(world.hit_events.tolist())
    assert world.touch_begin_events.dtype == hail.touch_event_dtype
    assert begun and begun[0][0] == a and begun[0][2] == hail.WITH_PLANE
    assert hits and hits[0][0] == a and hits[0][4] > 1.0


def test_rays_one_and_batch():
    world, handles = pile(n=100)
    world.step(1 / 60, n=10)
    h = int(handles[0])
    centre = world.position(h)
    hit = world.raycast(centre + np.array([0, 20, 0]), (0, -1, 0))
    assert hit is not None and hit.kind in ("sphere", "plane")
    below = world.raycast((50, 5, 50), (0, -1, 0))
    assert below.kind == "plane" and below.distance == pytest.approx(5.0)
    assert world.raycast((50, 5, 50), (0, 1, 0)) is None
    origins = np.column_stack([world.px, world.py + 10, world.pz])
    directions = np.tile([0, -1, 0], (len(world), 1))
    batch = world.raycast_batch(origins, directions)
    assert batch.dtype == hail.ray_hit_dtype and batch["hit"].all()
    for k in range(0, len(world), 9):
        one = world.raycast(origins[k], directions[k])
        assert batch["distance"][k] == one.distance and tuple(batch["point"][k]) == one.point
    assert h in world.overlap_sphere(centre, 0.01)
    with pytest.raises(hail.InvalidArgument):
        world.raycast((0, 0, 0), (0, 0, 0))


def test_terrain_from_numpy():
    x = np.arange(64, dtype=np.float32)
    heights = 2.0 * np.sin(0.2 * x)[None, :] * np.cos(0.15 * x)[:, None]
    terrain = hail.Terrain(heights, cell=1.0)
    assert terrain.shape == (64, 64) and terrain.extent == (0, 63, 0, 63)
    assert terrain.surface_height(10, 20) == pytest.approx(heights[20, 10], abs=1e-5)
    np.testing.assert_array_equal(terrain.heights, heights)
    world = hail.World(threads=1)
    world.set_terrain(terrain)
    assert world.has_terrain and world.terrain is terrain
    world.add_spheres(np.array([[20.0, 6, 20], [40, 6, 30]]), radii=0.5)
    world.step(1 / 60, n=120)
    for k in range(2):
        ground = terrain.surface_height(world.px[k], world.pz[k])
        assert world.py[k] > ground
    with pytest.raises(hail.InvalidArgument):
        hail.Terrain(np.zeros(5))


def test_step_releases_the_gil():
    world, _ = pile(threads=1, n=2000)
    ticks, refused = [], []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    stepper = threading.Thread(target=lambda: (world.step(1 / 60, n=150), done.set()))
    counter = threading.Thread(target=count)
    counter.start()
    stepper.start()
    while not done.is_set() and not refused:  # a call from this thread while the step runs is refused
        try:
            world.state_hash()
        except RuntimeError as error:
            refused.append(str(error))
    stepper.join()
    counter.join()
    assert refused and "stepping on another thread" in refused[0]
    assert len(ticks) > 5  # the counter ran while step() held no GIL
    world.step(1 / 60)  # and the world is whole afterwards


def test_step_from_threads_on_separate_worlds():
    worlds = [pile(threads=1, n=300, seed=3)[0] for _ in range(3)]
    threads = [threading.Thread(target=w.step, args=(1 / 60, 30)) for w in worlds]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len({w.state_hash() for w in worlds}) == 1

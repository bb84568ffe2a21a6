# World.from_scene reads a scene file as hail-bench run --scene does: stepped the same number
# of steps, both give the same state hash, on any thread count.
import json
import subprocess

import numpy as np
import pytest

import hail


def bench_hash(hail_bench, scene, tmp_path, *flags):
    out = tmp_path / "run.json"
    subprocess.run([hail_bench, "run", "--scene", str(scene), "--quiet", "--json", str(out), *flags],
                   check=True, capture_output=True)
    return json.loads(out.read_text())["state_hash"]


@pytest.mark.parametrize("threads", [1, 2])
def test_from_scene_matches_hail_bench(source_dir, hail_bench, tmp_path, threads):
    scene = source_dir / "data" / "scenes" / "terrain-rain.json"
    world = hail.World.from_scene(str(scene), threads=threads, spheres=600, steps=90)
    info = world.scene
    assert info["steps"] == 90 and len(info["handles"]) == 600 == len(world)
    world.step(info["dt"], n=info["steps"])
    expected = bench_hash(hail_bench, scene, tmp_path, "--threads", str(threads), "--spheres", "600", "--steps", "90")
    assert f"{world.state_hash():016x}" == expected


def test_from_scene_settings_override_the_file(source_dir, hail_bench, tmp_path):
    scene = source_dir / "data" / "scenes" / "bowl-pile.json"
    world = hail.World.from_scene(str(scene), threads=1, steps=40, spheres=300, solver="soft", soft_step_substeps=2)
    assert world.settings["solver"] == "soft" and world.settings["soft_step_substeps"] == 2
    world.step(world.scene["dt"], n=40)
    expected = bench_hash(hail_bench, scene, tmp_path, "--threads", "1", "--steps", "40", "--spheres", "300",
                          "--set", "solver=soft", "--set", "soft_step.substeps=2")
    assert f"{world.state_hash():016x}" == expected


def test_scene_file_errors(tmp_path):
    with pytest.raises(hail.FileError, match="nothing.json"):
        hail.World.from_scene(str(tmp_path / "nothing.json"))
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "hail-scene", "version": 1, "spheres": [], "typo": 1}')
    with pytest.raises(hail.InvalidArgument, match="typo"):
        hail.World.from_scene(str(bad))
    with pytest.raises(TypeError, match="no_such"):
        hail.World.from_scene(str(bad), no_such=1)


def test_scene_world_is_a_world(source_dir):
    world = hail.World.from_scene(str(source_dir / "data" / "scenes" / "implosion.json"), threads=1, spheres=100)
    assert world.has_terrain is False or world.has_terrain is True
    positions = world.positions
    assert positions.shape == (100, 3) and np.isfinite(positions).all()

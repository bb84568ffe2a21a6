# The Python examples run, small: the rain writes its plot, the benchmark finds equal hashes.
import os
import subprocess
import sys

import pytest


def run_example(source_dir, name, *args):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(source_dir / "examples" / "python" / name), *args],
                          check=True, capture_output=True, text=True, env=env)


def test_rain_on_terrain_writes_its_plot(source_dir, tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "rain.png"
    run = run_example(source_dir, "rain_on_terrain.py", "--spheres", "300", "--steps", "40", "--threads", "1",
                      "--out", str(out))
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "300 spheres, 40 steps" in run.stdout


def test_step_benchmark_hashes_agree(source_dir, hail_bench):
    run = run_example(source_dir, "step_benchmark.py", "--bench", hail_bench, "--scene",
                      str(source_dir / "data" / "scenes" / "terrain-rain.json"), "--spheres", "300", "--steps", "40",
                      "--repeat", "1")
    assert "(equal)" in run.stdout

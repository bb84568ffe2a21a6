#!/usr/bin/env python3
"""Times World.step from Python against hail-bench run on the same scene file.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/step_benchmark.py \\
        --bench build/release/bench/hail-bench --scene data/scenes/terrain-rain.json --spheres 4000

Both step the scene's default steps (or --steps) on the same thread count and report the median
ms per step over the steps after the first 60 (hail-bench run's own rule for runs over 120 steps),
then the state hashes, which must be equal. The difference is what crossing into Python costs per
call: step(dt) is one call per step, the GIL released inside it.
"""
import argparse
import json
import subprocess
import tempfile
import time

import numpy as np

import hail


def python_run(scene, spheres, steps, threads):
    world = hail.World.from_scene(scene, threads=threads, spheres=spheres, steps=steps)
    dt, steps = world.scene["dt"], world.scene["steps"]
    times = []
    for _ in range(steps):
        start = time.perf_counter()
        world.step(dt)
        times.append(time.perf_counter() - start)
    warmup = 60 if steps > 120 else 0
    return 1000 * float(np.median(times[warmup:])), f"{world.state_hash():016x}", steps


def bench_run(bench, scene, spheres, steps, threads):
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([bench, "run", "--scene", scene, "--spheres", str(spheres), "--steps", str(steps),
                        "--threads", str(threads), "--quiet", "--json", out.name], check=True, capture_output=True)
        result = json.load(open(out.name))
    return result["ms_per_step_median"], result["state_hash"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", required=True, help="path of hail-bench")
    parser.add_argument("--scene", default="data/scenes/terrain-rain.json")
    parser.add_argument("--spheres", type=int, default=4000)
    parser.add_argument("--steps", type=int, default=600)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3, help="alternating runs of each")
    args = parser.parse_args()

    py_ms, cpp_ms, hashes = [], [], set()
    for k in range(args.repeat):
        ms, h, steps = python_run(args.scene, args.spheres, args.steps, args.threads)
        py_ms.append(ms)
        hashes.add(h)
        ms, h = bench_run(args.bench, args.scene, args.spheres, args.steps, args.threads)
        cpp_ms.append(ms)
        hashes.add(h)
        print(f"  run {k + 1}/{args.repeat}: Python {py_ms[-1]:.3f} ms/step, hail-bench {cpp_ms[-1]:.3f} ms/step")
    py, cpp = float(np.median(py_ms)), float(np.median(cpp_ms))
    print(f"{args.scene}, {args.spheres} spheres, {steps} steps, {args.threads} thread(s), "
          f"median of {args.repeat} runs' medians:")
    print(f"  Python World.step  {py:.3f} ms/step")
    print(f"  hail-bench run     {cpp:.3f} ms/step   (Python / hail-bench = {py / cpp:.3f})")
    print(f"  state hashes       {', '.join(sorted(hashes))} ({'equal' if len(hashes) == 1 else 'DIFFERENT'})")
    return 0 if len(hashes) == 1 else 1


if __name__ == "__main__":
    raise SystemExit(main())

#!/usr/bin/env python3
"""Rain on a terrain made with numpy, and a plot of kinetic energy and overlap against time.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/rain_on_terrain.py [--out rain.png]

The terrain is a 128 x 128 height field from numpy; 2,000 spheres fall onto it in a jittered
block. Every step reads the arrays (no copy: world.py, world.radii, ...) to measure the deepest
overlap of a sphere with the ground; the plot (matplotlib, Agg: no display needed) goes to a PNG.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hail  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spheres", type=int, default=2000)
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--threads", type=int, default=0, help="0: all hardware threads")
    parser.add_argument("--out", default="rain.png")
    args = parser.parse_args()

    # Heights in metres, rows along z and columns along x, 1 m apart.
    x = np.arange(128, dtype=np.float32)
    heights = 6.0 * np.sin(0.06 * x)[None, :] * np.cos(0.05 * x)[:, None] + 0.5 * np.sin(0.4 * x)[:, None]
    terrain = hail.Terrain(heights, cell=1.0)

    world = hail.World(threads=args.threads, sleep=True)
    world.set_terrain(terrain, restitution=0.3, friction=0.6)
    rng = np.random.default_rng(2024)
    side = int(np.ceil(np.sqrt(args.spheres / 4)))
    grid = np.stack(np.meshgrid(np.arange(side), np.arange(4), np.arange(side), indexing="ij"), -1).reshape(-1, 3)
    positions = 32.0 + grid[: args.spheres] * 1.2 * np.array([1.0, 1.0, 1.0]) + np.array([0, 12, 0])
    positions += rng.uniform(-0.1, 0.1, positions.shape)
    world.add_spheres(positions, radii=rng.uniform(0.3, 0.5, len(positions)), masses=1.0)

    dt = 1 / 60
    times, energy, overlap = [], [], []
    for step in range(1, args.steps + 1):
        world.step(dt)
        ground = terrain.surface_height(world.px, world.pz)  # vectorised over every sphere
        depth = np.nan_to_num(ground + world.radii - world.py, nan=0.0)  # > 0: centre closer than r above
        times.append(step * dt)
        energy.append(world.kinetic_energy())
        overlap.append(max(0.0, float(depth.max())))

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(times, energy)
    top.set_ylabel("kinetic energy (J)")
    top.set_title(f"{len(world)} spheres on a numpy terrain, hash {world.state_hash():016x}")
    bottom.plot(times, 1000 * np.array(overlap))
    bottom.set_ylabel("deepest ground overlap (mm)\n(height above the surface point under the centre)")
    bottom.set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"{len(world)} spheres, {args.steps} steps: energy {energy[-1]:.1f} J, "
          f"asleep {int(world.sleeping.sum())}, plot written to {args.out}")


if __name__ == "__main__":
    main()

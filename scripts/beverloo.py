#!/usr/bin/env python3
"""Discharge of a flat-bottomed silo against Beverloo's law (docs/meshes.md, "Silo discharge").

A cylindrical silo (radius 12 d) with a flat bottom and a circular orifice of diameter D, both
triangle meshes (hail.TriangleMesh, two-sided shells), is filled with monodisperse spheres
(d = 1 m, density 1000 kg/m^3, friction 0.5, restitution 0.3) and drains under gravity. For each
D the mass flow rate W is the slope of the discharged mass against time while the discharge is
steady (from 400 to 1,400 spheres out, the fill still above the orifice by several D). Beverloo,
Leniger and van de Velde (1961) give

    W = C rho_b sqrt(g) (D - k d)^(5/2),

rho_b the bulk density of the fill, C about 0.58 and k about 1.4-1.5 (as Nedderman, "Statics and
Kinematics of Granular Materials", 1992, ch. 10, collects them). W^(2/5) is linear in D, so a
straight line through (D, W^(2/5)) gives k d (where it crosses zero) and C (from its slope).

    PYTHONPATH=build/release/python python3 scripts/beverloo.py [--threads 2] [--quick]

Writes docs/results/beverloo.csv and .json (machine, date, commit) and docs/images/beverloo.png;
about 2 minutes on 2 cores (--quick: two orifices, for a smoke test).
"""
import argparse
import datetime
import json
import math
import pathlib
import platform
import subprocess

import numpy as np

import hail

ROOT = pathlib.Path(__file__).resolve().parents[1]
D_SPHERE = 1.0  # m
DENSITY = 1000.0  # kg/m^3
MASS = DENSITY * math.pi / 6 * D_SPHERE**3
G = 9.81
SIDES = 64
SILO_RADIUS = 12.0 * D_SPHERE
WINDOW = (400, 1400)  # spheres out: the steady part fitted


def silo(orifice):
    """Cylinder wall (y 0..40 m) and a flat bottom ring (orifice / 2 .. SILO_RADIUS) at y = 0."""
    vertices, triangles = [], []
    ring = lambda r, y: [(r * math.cos(2 * math.pi * k / SIDES), y, r * math.sin(2 * math.pi * k / SIDES)) for k in range(SIDES)]
    rim, top, hole = ring(SILO_RADIUS, 0.0), ring(SILO_RADIUS, 40.0), ring(orifice / 2, 0.0)
    vertices = rim + top + hole
    for k in range(SIDES):
        n = (k + 1) % SIDES
        triangles += [(k, SIDES + k, SIDES + n), (k, SIDES + n, n)]  # wall
        triangles += [(2 * SIDES + k, k, n), (2 * SIDES + k, n, 2 * SIDES + n)]  # bottom ring
    # The polygon's orifice has a smaller area than the circle's: report the circle of equal area.
    effective = orifice * math.sqrt(SIDES / (2 * math.pi) * math.sin(2 * math.pi / SIDES))
    return hail.TriangleMesh(np.array(vertices, dtype=np.float32), np.array(triangles)), effective


def fill(count, seed=1):
    """A loose lattice inside the silo, from half a spacing above the floor, each sphere moved
    sideways at random by up to 0.15 d so that the fill settles into a random packing (a perfect
    lattice stays stacked in columns)."""
    rng = np.random.default_rng(seed)
    spacing = 1.35 * D_SPHERE
    side = int(2 * (SILO_RADIUS - 0.6 * D_SPHERE) / spacing) + 1
    points = []
    layer = 0
    while len(points) < count:
        for i in range(side):
            for j in range(side):
                x = -SILO_RADIUS + 0.6 * D_SPHERE + i * spacing
                z = -SILO_RADIUS + 0.6 * D_SPHERE + j * spacing
                if math.hypot(x, z) < SILO_RADIUS - 0.6 * D_SPHERE and len(points) < count:
                    points.append((x, 0.6 * D_SPHERE + layer * spacing, z))
        layer += 1
    points = np.array(points, dtype=np.float32)
    points[:, [0, 2]] += rng.uniform(-0.15, 0.15, size=(len(points), 2)).astype(np.float32) * D_SPHERE
    return points


def discharge(orifice, spheres, threads, dt=1 / 60, max_time=60.0):
    mesh, effective = silo(orifice)
    world = hail.World(threads=threads)
    world.add_mesh(mesh, restitution=0.3, friction=0.5)
    world.add_spheres(fill(spheres), radii=D_SPHERE / 2, masses=MASS, restitution=0.3, friction=0.5)
    times, out = [], []
    t = 0.0
    while t < max_time:
        world.step(dt, 6)
        t += 6 * dt
        gone = int(np.count_nonzero(world.py < -D_SPHERE))
        times.append(t)
        out.append(gone)
        if gone >= WINDOW[1] + 100:
            break
    times, out = np.array(times), np.array(out)
    steady = (out >= WINDOW[0]) & (out <= WINDOW[1])
    if np.count_nonzero(steady) < 4:
        raise SystemExit(f"D = {orifice}: only {out[-1]} spheres out after {t:.0f} s (jammed?)")
    slope = np.polyfit(times[steady], out[steady], 1)[0]  # spheres per second
    # The fill's bulk density: the spheres' mass over the volume they fill at the start of the window.
    return {
        "orifice_m": orifice,
        "orifice_effective_m": effective,
        "flow_spheres_per_s": slope,
        "flow_kg_per_s": slope * MASS,
        "window_s": [float(times[steady][0]), float(times[steady][-1])],
        "nan": int(np.count_nonzero(~np.isfinite(world.py))),
    }


def bulk_density(threads):
    """Mass per volume of the fill at rest in the closed silo (a pin-hole orifice): sphere centres
    counted in a cylinder two diameters clear of the wall, the floor and the surface."""
    mesh, _ = silo(0.01)
    world = hail.World(threads=threads)
    world.add_mesh(mesh, restitution=0.3, friction=0.5)
    world.add_spheres(fill(3000), radii=D_SPHERE / 2, masses=MASS, restitution=0.3, friction=0.5)
    world.step(1 / 60, 600)
    x, y, z = (np.asarray(a) for a in (world.px, world.py, world.pz))
    inner = SILO_RADIUS - 2 * D_SPHERE
    low, high = 2 * D_SPHERE, np.percentile(y, 80) - 2 * D_SPHERE
    inside = np.count_nonzero((np.hypot(x, z) < inner) & (y > low) & (y < high))
    return inside * MASS / (math.pi * inner**2 * (high - low))


def measure(orifices, spheres, threads, log=lambda *a, **k: None):
    """The discharge of each orifice and the Beverloo fit through them: (rows, fit)."""
    rho_b = bulk_density(threads)
    rows = []
    for D in orifices:
        r = discharge(D, spheres, threads)
        rows.append(r)
        log(f"D = {D:4.1f} d: {r['flow_spheres_per_s']:7.1f} spheres/s ({r['flow_kg_per_s']:8.0f} kg/s), "
            f"steady {r['window_s'][0]:.1f}-{r['window_s'][1]:.1f} s", flush=True)
    D = np.array([r["orifice_effective_m"] for r in rows])
    W = np.array([r["flow_kg_per_s"] for r in rows])
    slope, intercept = np.polyfit(D, W ** 0.4, 1)
    fit = {"C": slope**2.5 / (rho_b * math.sqrt(G)), "k": -intercept / slope / D_SPHERE, "bulk_density_kg_m3": rho_b,
           "packing_fraction": rho_b / DENSITY, "slope": slope, "intercept": intercept}
    return rows, fit


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--spheres", type=int, default=6000)
    p.add_argument("--quick", action="store_true", help="two orifices only, no files written")
    args = p.parse_args()
    orifices = [6.0, 9.0] if args.quick else [5.0, 6.0, 7.0, 8.0, 9.0]
    rows, fit = measure(orifices, args.spheres, args.threads, log=print)
    C, k, rho_b = fit["C"], fit["k"], fit["bulk_density_kg_m3"]
    print(f"bulk density {rho_b:.0f} kg/m^3 (packing {rho_b / DENSITY:.3f}); Beverloo fit: C = {C:.3f}, k = {k:.2f} "
          f"(literature: C about 0.58, k about 1.4-1.5)")
    D = np.array([r["orifice_effective_m"] for r in rows])
    W = np.array([r["flow_kg_per_s"] for r in rows])
    if args.quick:
        return
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    meta = {"date": datetime.date.today().isoformat(), "commit": commit or "unknown",
            "machine": platform.processor() or platform.machine(), "threads": args.threads, "spheres": args.spheres,
            "command": "PYTHONPATH=build/release/python python3 scripts/beverloo.py"}
    try:
        meta["machine"] = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    results = ROOT / "docs" / "results"
    results.mkdir(parents=True, exist_ok=True)
    json.dump({**meta, "fit": fit, "runs": rows}, open(results / "beverloo.json", "w"), indent=2)
    with open(results / "beverloo.csv", "w") as f:
        f.write(f"# Silo discharge against Beverloo's law: {meta['command']}; {meta['machine']}, {meta['date']}, "
                f"commit {meta['commit']}\n")
        f.write("orifice_m,orifice_effective_m,flow_spheres_per_s,flow_kg_per_s,beverloo_kg_per_s\n")
        for r in rows:
            law = C * rho_b * math.sqrt(G) * max(r["orifice_effective_m"] - k * D_SPHERE, 0.0) ** 2.5
            f.write(f"{r['orifice_m']},{r['orifice_effective_m']:.4f},{r['flow_spheres_per_s']:.2f},"
                    f"{r['flow_kg_per_s']:.1f},{law:.1f}\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(D, W ** 0.4, "o", label="hail")
    xs = np.linspace(k * D_SPHERE, D.max() * 1.05, 50)
    ax.plot(xs, fit["slope"] * xs + fit["intercept"], "-", label=f"fit: C = {C:.2f}, k = {k:.2f}")
    ax.set_xlabel("orifice diameter D / d")
    ax.set_ylabel("W^(2/5), (kg/s)^(2/5)")
    ax.set_title("Silo discharge, Beverloo's law")
    ax.legend()
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "images" / "beverloo.png", dpi=110)


if __name__ == "__main__":
    main()

# Silo discharge through a mesh orifice follows Beverloo's law (scripts/beverloo.py, docs/meshes.md):
# two orifices, 6 and 9 sphere diameters, on the script's silo. The bounds: C within 20% of the
# literature's 0.58 and k from 1 to 2.5, the spread reported for frictional spheres (Nedderman 1992,
# ch. 10); a silo whose floor leaked, or whose flow did not grow as (D - k d)^(5/2), falls outside.
import importlib.util
import pathlib

SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "beverloo.py"


def test_silo_discharge_follows_beverloo():
    spec = importlib.util.spec_from_file_location("beverloo", SCRIPT)
    beverloo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(beverloo)
    rows, fit = beverloo.measure([6.0, 9.0], spheres=6000, threads=2)
    assert all(r["nan"] == 0 for r in rows)
    assert 0.55 < fit["packing_fraction"] < 0.66  # a random packing, not the start's lattice
    assert 0.45 < fit["C"] < 0.7
    assert 1.0 < fit["k"] < 2.5

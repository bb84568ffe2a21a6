# hail.TriangleMesh and World.add_mesh: a mesh from numpy arrays or a file, spheres resting on it,
# and the errors for bad input (docs/meshes.md).
import numpy as np
import pytest

import hail


def floor(half=5.0, cells=4):
    """A flat floor at y = 0 over [-half, half]^2: an open (two-sided) mesh of 2 cells^2 triangles."""
    xs = np.linspace(-half, half, cells + 1)
    vertices = np.array([(x, 0.0, z) for z in xs for x in xs], dtype=np.float32)
    at = lambda i, j: j * (cells + 1) + i
    quads = [(at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)) for j in range(cells) for i in range(cells)]
    indices = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], dtype=np.int64)
    return hail.TriangleMesh(vertices, indices)


def test_spheres_come_to_rest_on_a_mesh_floor():
    mesh = floor()
    assert mesh.triangle_count == 32 and not mesh.closed
    assert mesh.vertices.shape == (25, 3) and mesh.indices.shape == (32, 3)
    world = hail.World(threads=1)
    assert world.add_mesh(mesh, position=(0, 1, 0), restitution=0.2) == 0
    assert world.mesh_count == 1
    world.add_spheres(np.array([(0.1, 3.0, 0.2), (1.3, 4.0, -0.7)]), radii=0.25, masses=1.0)
    world.step(1 / 60, 180)
    assert np.allclose(world.py, 1.25, atol=0.0025)  # on the moved floor, within 1% of a radius
    assert np.all(np.abs(world.vy) < 1e-3)


def test_a_mesh_loads_from_an_obj_file(tmp_path):
    path = tmp_path / "tetra.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    mesh = hail.TriangleMesh.load(str(path))
    assert mesh.triangle_count == 4 and mesh.closed
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(hail.FileError, match="bad.obj:2"):
        hail.TriangleMesh.load(str(bad))


def test_bad_meshes_and_placements_are_refused():
    with pytest.raises(hail.InvalidArgument, match="not below the vertex count"):
        hail.TriangleMesh(np.zeros((3, 3)), np.array([[0, 1, 3]]))
    with pytest.raises(hail.InvalidArgument, match="indices"):
        hail.TriangleMesh(np.zeros((3, 3)), np.zeros((2, 2)))
    world = hail.World(threads=1)
    with pytest.raises(hail.InvalidArgument, match="scale"):
        world.add_mesh(floor(), scale=0)
    assert world.mesh_count == 0


def test_spheres_fall_asleep_on_a_mesh():
    world = hail.World(threads=1, sleep=True)
    world.add_mesh(floor())
    world.add_spheres(np.array([(0.1, 2.0, 0.2), (1.5, 3.0, 1.0)]), radii=0.25, masses=1.0)
    world.step(1 / 60, 180)
    assert world.sleeping.all()


def test_a_ray_reports_the_mesh_it_hits():
    world = hail.World(threads=1)
    world.add_mesh(floor(), position=(0, 2, 0))
    hit = world.raycast((0.3, 5.0, 0.2), (0, -1, 0))
    assert hit.kind == "mesh" and hit.index == 0
    assert hit.distance == pytest.approx(3.0)
    assert world.raycast((0.3, 5.0, 0.2), (0, -1, 0), meshes=False) is None
    batch = world.raycast_batch(np.array([(0.3, 5.0, 0.2)]), np.array([(0, -1, 0)]))
    assert batch["hit"][0] and batch["kind"][0] == hail.KIND_MESH

# ParaView frames (scenes/vtk_frames.h) read back: .vtu by meshio (Debian's python3-meshio),
# .vtp by a small reader of VTK's raw appended XML (meshio reads no PolyData), the .pvd index by
# ElementTree; and hail-bench run --vtk writes the same files.
import pathlib
import re
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import hail

VTK_TYPES = {"Float32": "<f4", "UInt8": "u1", "UInt64": "<u8", "Int64": "<i8"}


def read_vtk_xml(path):
    """Every DataArray of a raw-appended VTK XML file (header_type UInt64), by name."""
    raw = pathlib.Path(path).read_bytes()
    start = raw.index(b"_", raw.index(b"<AppendedData")) + 1
    head = ET.fromstring(raw[: raw.index(b"<AppendedData")] + b"</VTKFile>")
    assert head.get("header_type") == "UInt64" and head.get("byte_order") == "LittleEndian"
    arrays = {}
    for a in head.iter("DataArray"):
        at = start + int(a.get("offset"))
        size = int(np.frombuffer(raw, "<u8", 1, at)[0])
        values = np.frombuffer(raw[at + 8 : at + 8 + size], VTK_TYPES[a.get("type")])
        n = int(a.get("NumberOfComponents"))
        arrays[a.get("Name")] = values.reshape(-1, n) if n > 1 else values
    return head, arrays


def falling_world():
    world = hail.World(threads=1, sleep=True)
    world.add_plane((0, 1, 0), 0.0)
    rng = np.random.default_rng(7)
    world.add_spheres(rng.uniform((0, 0.5, 0), (4, 4, 4), size=(50, 3)), radii=0.2,
                      velocities=rng.normal(size=(50, 3)))
    return world


def expected_data(world):
    """What a frame of the world holds now (copies: the views follow the world's next steps)."""
    v = world.velocities
    return {"Points": world.positions, "radius": world.radii.copy(), "velocity": v,
            "speed": np.sqrt((v * v).sum(axis=1)), "sleeping": world.sleeping.astype(np.uint8),
            "handle": world.handles.copy()}


def test_vtp_frames_and_index(tmp_path):
    world = falling_world()
    frames = hail.VtkFrames(str(tmp_path / "out"))
    for k in range(3):
        expected = expected_data(world)
        path = frames.write(world, k / 60)
        world.step(1 / 60, n=20)
    assert frames.frame_count == 3 and pathlib.Path(path).name == "frame_000002.vtp"
    head, arrays = read_vtk_xml(path)
    assert head.get("type") == "PolyData"
    for name, values in expected.items():
        np.testing.assert_array_equal(arrays[name], values, err_msg=name)
    index = ET.parse(frames.index_path).getroot()
    entries = [(float(d.get("timestep")), d.get("file")) for d in index.iter("DataSet")]
    assert entries == [(0.0, "frame_000000.vtp"), (pytest.approx(1 / 60), "frame_000001.vtp"),
                       (pytest.approx(2 / 60), "frame_000002.vtp")]
    assert arrays["Points"].shape == (50, 3)
    assert arrays["connectivity"].tolist() == list(range(50))


def test_vtu_frame_reads_back_with_meshio(tmp_path):
    meshio = pytest.importorskip("meshio")
    world = falling_world()
    world.step(1 / 60, n=90)
    frames = hail.VtkFrames(str(tmp_path), format="vtu", name="rain")
    mesh = meshio.read(frames.write(world, 1.5))
    expected = expected_data(world)
    assert len(mesh.points) == len(world) == 50
    np.testing.assert_array_equal(mesh.points, expected["Points"])
    for name in ("radius", "velocity", "speed", "sleeping", "handle"):
        values = np.asarray(mesh.point_data[name])  # meshio keeps one component as (n, 1)
        np.testing.assert_array_equal(values.reshape(expected[name].shape), expected[name], err_msg=name)
    assert mesh.cells[0].type == "vertex" and len(mesh.cells[0].data) == 50
    _, arrays = read_vtk_xml(tmp_path / "rain_000000.vtu")
    np.testing.assert_array_equal(arrays["angular_velocity"], world.angular_velocities)


def test_bad_folder_is_a_file_error(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(hail.FileError):
        hail.VtkFrames(str(tmp_path / "file" / "sub"))
    with pytest.raises(hail.InvalidArgument):
        hail.VtkFrames(str(tmp_path), format="csv")


def test_hail_bench_writes_frames(source_dir, hail_bench, tmp_path):
    scene = source_dir / "data" / "scenes" / "terrain-rain.json"
    out = tmp_path / "vtk"
    run = subprocess.run([hail_bench, "run", "--scene", str(scene), "--spheres", "300", "--steps", "30",
                          "--threads", "1", "--vtk", str(out), "--vtk-every", "10", "--quiet"],
                         check=True, capture_output=True, text=True)
    files = sorted(p.name for p in out.glob("*.vtp"))
    assert files == [f"frame_{k:06d}.vtp" for k in range(4)]  # steps 0, 10, 20, 30
    index = ET.parse(out / "frame.pvd").getroot()
    times = [float(d.get("timestep")) for d in index.iter("DataSet")]
    assert times == pytest.approx([k * 10 / 60 for k in range(4)], rel=1e-6)
    world = hail.World.from_scene(str(scene), threads=1, spheres=300)
    world.step(world.scene["dt"], n=30)
    _, arrays = read_vtk_xml(out / "frame_000003.vtp")
    np.testing.assert_array_equal(arrays["Points"], world.positions)
    assert re.search(r"hash [0-9a-f]{16}", run.stdout).group(0) == f"hash {world.state_hash():016x}"

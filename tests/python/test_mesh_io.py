"""Meshes in and out of Python: every shared mesh against `lodforge info` and `lodforge convert`, the NumPy
views, meshes built from arrays, and errors."""
import gc

import numpy as np
import pytest

import lodforge
from conftest import SHARED, cli_json, run_cli, shared_meshes

MESHES = shared_meshes()


def test_the_shared_meshes_are_there():
    assert len(MESHES) >= 20, f"expected the shared meshes under {SHARED}"


@pytest.mark.parametrize("path", MESHES, ids=lambda p: str(p.relative_to(SHARED)))
def test_round_trip_matches_the_cli(path, tmp_path):
    expected = cli_json("info", "--json", path)
    # The same summary from Python (same reader, same counting).
    assert lodforge.info(path) == expected
    mesh = lodforge.read_mesh(str(path), validate=not any(f["severity"] == "error" for f in expected["validation"]))
    assert (mesh.point_count, mesh.vertex_count, mesh.triangle_count) == (
        expected["vertices"], expected["wedges"], expected["triangles"])
    assert mesh.positions.shape == (expected["wedges"], 3)
    assert mesh.indices.shape == (expected["triangles"], 3)
    if mesh.triangle_count == 0:
        return
    # Written from Python, the file is the one `lodforge convert` writes, byte for byte.
    ours, theirs = tmp_path / "py.ply", tmp_path / "cli.ply"
    lodforge.write_mesh(mesh, str(ours))
    run_cli("convert", path, theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    again = lodforge.read_mesh(str(ours))
    written = cli_json("info", "--json", ours)
    assert (again.point_count, again.vertex_count, again.triangle_count) == (
        written["vertices"], written["wedges"], written["triangles"])
    assert again.triangle_count == expected["triangles"]


def test_arrays_are_views_into_the_mesh(bunny):
    mesh = lodforge.read_mesh(str(bunny))
    positions = mesh.positions
    assert positions.dtype == np.float32 and positions.flags["C_CONTIGUOUS"]
    assert np.shares_memory(positions, mesh.positions)  # the same buffer each time: no copy
    positions[0] = (1.5, 2.5, 3.5)
    assert tuple(mesh.positions[0]) == (1.5, 2.5, 3.5)
    assert mesh.bounds[1][2] >= 3.5  # the core sees the write
    indices = mesh.indices
    assert indices.dtype == np.uint32 and indices.shape == (mesh.triangle_count, 3)
    # A view keeps its mesh alive.
    del mesh
    gc.collect()
    assert positions[0, 0] == np.float32(1.5)
    assert int(indices.max()) < positions.shape[0]


def test_views_stay_valid_when_an_array_is_replaced(bunny):
    mesh = lodforge.read_mesh(str(bunny))
    old = mesh.positions
    first = old[:4].copy()
    mesh.positions = np.zeros((10, 3), np.float32)
    mesh.positions = np.ones((20, 3), np.float32)
    assert mesh.positions.shape == (20, 3)
    np.testing.assert_array_equal(old[:4], first)
    same = mesh.positions
    mesh.positions = np.full((20, 3), 7, np.float32)  # same length: in place, views see it
    assert same[3, 1] == 7


def test_mesh_from_arrays_simplifies_and_writes(tmp_path):
    # A 40 x 40 grid of quads.
    n = 40
    ys, xs = np.mgrid[0:n + 1, 0:n + 1]
    positions = np.stack([xs.ravel(), ys.ravel(), np.sin(xs.ravel() / 5.0)], axis=1).astype(np.float64)
    v = (ys[:-1, :-1] * (n + 1) + xs[:-1, :-1]).ravel()
    indices = np.concatenate([np.stack([v, v + 1, v + n + 2], 1), np.stack([v, v + n + 2, v + n + 1], 1)])
    mesh = lodforge.Mesh(positions, indices)
    assert mesh.triangle_count == 2 * n * n and mesh.positions.dtype == np.float32
    mesh.colors = np.tile(np.array([[1, 0, 0, 1]], np.float32), (mesh.vertex_count, 1))
    mesh.texcoords = [positions[:, :2] / n]
    assert len(mesh.texcoords) == 1 and mesh.texcoords[0].shape == (mesh.vertex_count, 2)
    r = lodforge.simplify(mesh, triangles=500)
    assert 0 < r.triangles <= 500 and r.mesh.colors.shape[0] == r.mesh.vertex_count
    out = tmp_path / "grid.glb"
    lodforge.write_mesh(r.mesh, str(out))
    assert lodforge.info(out)["triangles"] == r.triangles


def test_bad_arrays_raise_lodforge_error(tmp_path):
    with pytest.raises(lodforge.Error, match="shape"):
        lodforge.Mesh(np.zeros((4, 2)), np.zeros((1, 3)))
    mesh = lodforge.Mesh(np.zeros((3, 3)), np.array([[0, 1, 7]]))
    with pytest.raises(lodforge.Error) as e:
        lodforge.simplify(mesh, ratio=0.5)
    assert e.value.kind == "invalid" and "does not exist" in str(e.value)
    with pytest.raises(lodforge.Error, match="does not exist"):
        lodforge.write_lod_pack(mesh, tmp_path / "pack", source_path=SHARED / "scan-bunny/bun_zipper.ply")
    mesh = lodforge.Mesh(np.eye(3), np.array([[0, 1, 2]]))
    mesh.normals = np.zeros((2, 3))  # a length the positions do not have
    with pytest.raises(lodforge.Error) as e:
        lodforge.write_mesh(mesh, tmp_path / "never.ply")
    assert e.value.kind == "invalid"
    assert list(tmp_path.iterdir()) == []


def test_a_bad_file_raises_an_error_naming_it(tmp_path):
    bad = tmp_path / "broken.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nend_header\n\x00")
    with pytest.raises(lodforge.Error) as e:
        lodforge.read_mesh(str(bad))
    assert str(bad) in str(e.value) and e.value.kind == "format"
    assert isinstance(e.value, RuntimeError)
    cli_message = run_cli("info", bad, check=False).stderr
    assert str(e.value) in cli_message  # the CLI's message, word for word
    with pytest.raises(lodforge.Error, match="missing.obj"):
        lodforge.read_mesh(str(tmp_path / "missing.obj"))
    with pytest.raises(lodforge.Error, match="nowhere"):
        lodforge.write_mesh(lodforge.read_mesh(str(SHARED / "tex-duck/glTF_Binary/Duck.glb")), str(tmp_path / "nowhere" / "x.ply"))


def test_materials_and_textures(spot):
    mesh = lodforge.read_mesh(spot)  # any os.PathLike
    assert len(mesh.materials) >= 1
    assert mesh.materials[0].base_color_texture["path"].endswith(".png")
    assert len(mesh.texcoords) == 1
    duck = lodforge.read_mesh(str(SHARED / "tex-duck/glTF_Binary/Duck.glb"))
    assert duck.materials[0].base_color_texture["embedded"]

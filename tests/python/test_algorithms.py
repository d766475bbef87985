"""Every algorithm of the module against the CLI on the same input: simplify, LOD chains, compare,
packs, octrees and LODStrips."""
import json

import numpy as np
import pytest

import lodforge
from conftest import SHARED, cli_json, run_cli

DRAGON = SHARED / "scan-dragon" / "dragon_vrip_res4.ply"


def test_simplify_matches_the_cli(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    r = lodforge.simplify(mesh, ratio=0.1)
    out = tmp_path / "cli.ply"
    run_cli("simplify", bunny, "--ratio", "0.1", "-o", out)
    cli_mesh = lodforge.read_mesh(str(out))
    assert r.triangles == cli_mesh.triangle_count == r.mesh.triangle_count
    assert r.reason == "target_reached" and r.mode == "collapse"
    assert r.triangles <= r.target_triangles
    np.testing.assert_allclose(r.mesh.positions, cli_mesh.positions, rtol=0, atol=0)
    np.testing.assert_array_equal(r.mesh.indices, cli_mesh.indices)


def test_simplify_options_follow_the_cli(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    r = lodforge.simplify(mesh, triangles=2000, placement="half-edge", weights={"normal": 0.5}, mode="collapse")
    out = tmp_path / "cli.ply"
    run_cli("simplify", bunny, "--triangles", "2000", "--placement", "half-edge", "--weights", "normal=0.5", "-o", out)
    np.testing.assert_array_equal(r.mesh.indices, lodforge.read_mesh(str(out)).indices)
    c = lodforge.simplify(mesh, ratio=0.05, mode="cluster")
    run_cli("simplify", bunny, "--ratio", "0.05", "--mode", "cluster", "-o", out)
    assert c.mode == "cluster" and c.triangles == lodforge.read_mesh(str(out)).triangle_count
    p = lodforge.simplify(mesh, preset="mobile")
    run_cli("simplify", bunny, "--preset", "mobile", "-o", out)
    assert p.triangles == lodforge.read_mesh(str(out)).triangle_count
    with pytest.raises(lodforge.Error, match="exactly one"):
        lodforge.simplify(mesh, ratio=0.5, triangles=10)
    with pytest.raises(lodforge.Error, match="ratio must be in"):
        lodforge.simplify(mesh, ratio=1.5)
    with pytest.raises(lodforge.Error, match="unknown attribute"):
        lodforge.simplify(mesh, ratio=0.5, weights={"shininess": 1})
    with pytest.raises(lodforge.Error, match="no-such-preset"):
        lodforge.simplify(mesh, preset="no-such-preset")


def test_lod_chain_matches_the_cli(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    chain = lodforge.build_lod_chain(mesh, levels=[0.5, 0.1, 0.02])
    # build_lod_chain keeps input vertices (half-edge: its levels share one vertex buffer).
    run_cli("lod", bunny, "--levels", "0.5,0.1,0.02", "--placement", "half-edge", "-o", tmp_path / "lod")
    doc = json.loads((tmp_path / "lod" / "lods.json").read_text())
    assert [l.triangles for l in chain.levels] == [l["triangles"] for l in doc["levels"]]
    assert [l.mesh.point_count for l in chain.levels] == [l["vertices"] for l in doc["levels"]]
    assert chain.levels[0].distance is None and chain.levels[0].reason == "input"
    for level, cli_level in zip(chain.levels[1:], doc["levels"][1:]):
        assert level.distance.hausdorff == pytest.approx(cli_level["error"]["hausdorff"], rel=1e-12)
        assert level.accumulated_error_relative >= level.step_error_relative > 0
    # The shared buffer: level k's range indexes a prefix of the shared vertices.
    first, count, verts = chain.shared_ranges[2]
    flat = chain.shared.indices.reshape(-1)[first:first + count]
    assert count == 3 * chain.levels[2].triangles and flat.max() < verts
    assert chain.levels[3].input_vertex.max() < mesh.vertex_count
    with pytest.raises(lodforge.Error, match="not fewer than the previous"):
        lodforge.build_lod_chain(mesh, levels=[0.1, 0.5])


def test_compare_matches_the_cli(bunny, tmp_path):
    low = tmp_path / "low.ply"
    run_cli("simplify", bunny, "--ratio", "0.05", "-o", low)
    reference, test = lodforge.read_mesh(str(bunny)), lodforge.read_mesh(str(low))
    d = lodforge.compare(reference, test, samples=20000, vertex_errors=True)
    expected = cli_json("compare", bunny, low, "--samples", "20000", "--json")
    assert d.hausdorff == pytest.approx(expected["hausdorff"], rel=1e-12)
    assert d.mean == pytest.approx(expected["mean"], rel=1e-12)
    assert d.test_to_reference.samples == expected["test_to_reference"]["samples"]
    assert d.hausdorff > 0 and d.vertex_errors.shape == (test.vertex_count,)
    assert lodforge.compare(reference, reference, samples=20000).hausdorff_relative < 1e-9


@pytest.mark.skipif(not lodforge.HAVE_RENDER, reason="this build has no renderer (LODFORGE_BUILD_RENDER=OFF)")
def test_render_compare_matches_the_cli(spot, tmp_path):
    low = tmp_path / "low.obj"
    run_cli("simplify", spot, "--ratio", "0.1", "-o", low)
    img = lodforge.render_compare(lodforge.read_mesh(str(spot)), lodforge.read_mesh(str(low)), size=64)
    expected = cli_json("compare", spot, low, "--render", "--render-size", "64", "--json")["image"]
    assert len(img.views) == 14 and img.size == 64
    assert img.mean_abs == pytest.approx(expected["mean_abs"], rel=1e-9)
    assert img.silhouette == pytest.approx(expected["silhouette"], rel=1e-9)


def test_pack_is_byte_identical_to_the_cli(spot, tmp_path):
    ours = lodforge.write_lod_pack(str(spot), str(tmp_path / "py"), preset="mobile")
    run_cli("pack", spot, "--preset", "mobile", "-o", tmp_path / "cli")
    assert ours["files"] and ours["glb"]
    for name in ours["files"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert sorted(p.name for p in (tmp_path / "cli").iterdir()) == sorted(ours["files"])
    assert json.loads(ours["manifest"])["levels"][1]["triangles"] == ours["levels"][1]["triangles"]


def test_pack_with_a_preset_dict_and_a_mesh(bunny, tmp_path):
    preset = {"name": "two-levels", "method": "collapse", "levels": [{"ratio": 0.3}, {"ratio": 0.05}]}
    mesh = lodforge.read_mesh(str(bunny))
    r = lodforge.write_lod_pack(mesh, str(tmp_path / "py"), preset=preset, source_path=str(bunny))
    preset_file = tmp_path / "two.json"
    preset_file.write_text(json.dumps(preset))
    cli = cli_json("pack", bunny, "--preset", preset_file, "-o", tmp_path / "cli", "--json")
    assert [l["triangles"] for l in r["levels"]] == [l["triangles"] for l in cli["levels"]]
    assert len(r["levels"]) == 3
    # The same preset as a file (a pathlib.Path), with the mesh read from its path.
    from_file = lodforge.write_lod_pack(bunny, tmp_path / "py2", preset=preset_file)
    assert [l["triangles"] for l in from_file["levels"]] == [l["triangles"] for l in r["levels"]]
    assert (tmp_path / "py2" / "pack.json").read_bytes() == (tmp_path / "cli" / "pack.json").read_bytes()
    with pytest.raises(lodforge.Error, match="source_path"):
        lodforge.write_lod_pack(mesh, str(tmp_path / "x"), preset=preset)
    with pytest.raises(lodforge.Error, match="preset"):
        lodforge.write_lod_pack(mesh, str(tmp_path / "x"), preset={"levels": "many"}, source_path=str(bunny))


def test_octree_build_and_extract_match_the_cli(tmp_path):
    stats = lodforge.build_octree(str(DRAGON), str(tmp_path / "py.lfo"), max_triangles=2000, threads=1)
    run_cli("octree", "build", DRAGON, "-o", tmp_path / "cli.lfo", "--max-triangles", "2000", "--threads", "1")
    assert (tmp_path / "py.lfo").read_bytes() == (tmp_path / "cli.lfo").read_bytes()
    assert stats["levels"] >= 2 and stats == {**lodforge.octree_info(str(tmp_path / "py.lfo")), "warnings": stats["warnings"]}
    # One core description: the dict is the CLI's JSON, key for key and value for value.
    info = lodforge.octree_info(str(tmp_path / "py.lfo"))
    assert info == cli_json("octree", "info", tmp_path / "cli.lfo", "--json")
    assert {"triangles_per_depth", "bounds", "root_cube", "attributes", "max_depth"} <= info.keys()
    level = 1
    m = lodforge.extract_octree(str(tmp_path / "py.lfo"), level=level)
    assert m.triangle_count == stats["triangles_per_level"][level]
    run_cli("octree", "extract", tmp_path / "cli.lfo", "--level", level, "-o", tmp_path / "l1.ply")
    assert lodforge.read_mesh(str(tmp_path / "l1.ply")).triangle_count == m.triangle_count
    (lo, hi) = m.bounds
    center = [(a + b) / 2 for a, b in zip(lo, hi)]
    view = lodforge.extract_octree(str(tmp_path / "py.lfo"), screen_error=2.0,
                                   camera=(center[0], center[1], center[2] + 0.5, *center, 60))
    assert 0 < view.triangle_count
    with pytest.raises(lodforge.Error, match="exactly one"):
        lodforge.extract_octree(str(tmp_path / "py.lfo"))
    with pytest.raises(lodforge.Error, match="must be a .ply"):
        lodforge.build_octree(str(SHARED / "tex-spot/spot_triangulated.obj"), str(tmp_path / "x.lfo"))


def test_lodstrips_build_and_extract_match_the_cli(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    info = lodforge.build_lodstrips(mesh, str(tmp_path / "py.lodstrips"), coarsest=0.02)
    run_cli("strips", bunny, "--coarsest", "0.02", "-o", tmp_path / "cli.lodstrips")
    assert (tmp_path / "py.lodstrips").read_bytes() == (tmp_path / "cli.lodstrips").read_bytes()
    assert info["max_triangles"] == mesh.triangle_count and info["min_triangles"] < mesh.triangle_count * 0.03
    full = lodforge.extract_lodstrips(str(tmp_path / "py.lodstrips"))
    assert full.triangle_count == mesh.triangle_count
    half = lodforge.extract_lodstrips(str(tmp_path / "py.lodstrips"), triangles=mesh.triangle_count // 2)
    run_cli("strips", "extract", tmp_path / "cli.lodstrips", "--triangles", mesh.triangle_count // 2, "-o", tmp_path / "h.ply")
    assert half.triangle_count == lodforge.read_mesh(str(tmp_path / "h.ply")).triangle_count <= mesh.triangle_count // 2
    with pytest.raises(lodforge.Error, match="py.ply"):
        lodforge.extract_lodstrips(str(tmp_path / "py.ply"))

"""The Dask runner (python/lodforge/dask_batch.py) on a LocalCluster with 2 workers against small shared
meshes: packs byte-identical to `lodforge batch`, the same report and state file (a re-run skips), and
one bad asset reported without stopping the others.

Environment (set by ctest, tests/CMakeLists.txt): LODFORGE_BIN (the CLI), LODFORGE_SHARED_DATA,
LODFORGE_PYTHON_SOURCE (the package's source folder; the runner is started as a script so the
package's __init__ and the compiled module are not needed).
"""

import json
import os
import shutil
import subprocess
import sys

import pytest

LODFORGE = os.environ["LODFORGE_BIN"]
SHARED = os.environ["LODFORGE_SHARED_DATA"]
RUNNER = os.path.join(os.environ["LODFORGE_PYTHON_SOURCE"], "lodforge", "dask_batch.py")

FILES = {
    "scans/dragon.ply": "scan-dragon/dragon_vrip_res4.ply",
    "scans/laurana500.ply": "tex-ply-wedge-uv/laurana500.ply",
    "scans/laurana500.png": None,  # the PLY's TextureFile, beside it
    "color.ply": "color-open3d-small/color.ply",
    "duck/Duck.gltf": "tex-duck/glTF/Duck.gltf",
}


MESHES = [name for name, source in FILES.items() if source]


@pytest.fixture
def tree(tmp_path):
    for name, source in FILES.items():
        target = tmp_path / "in" / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(os.path.join(SHARED, source or "tex-ply-wedge-uv/" + os.path.basename(name)), target)
    # The Duck's buffer and texture sit beside it.
    for extra in ("Duck0.bin", "DuckCM.png"):
        shutil.copyfile(os.path.join(SHARED, "tex-duck/glTF", extra), tmp_path / "in" / "duck" / extra)
    return tmp_path


def run_dask(source, output, *extra):
    return subprocess.run([sys.executable, RUNNER, str(source), "-o", str(output), "--workers", "2",
                           "--lodforge", LODFORGE, *extra],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)


def pack_files(root):
    """Every file under root except the batch's own state and report, relative path -> bytes."""
    files = {}
    for folder, _, names in os.walk(root):
        for name in names:
            if name in ("batch-state.json", "batch-report.json"):
                continue
            path = os.path.join(folder, name)
            with open(path, "rb") as f:
                files[os.path.relpath(path, root)] = f.read()
    return files


def test_dask_packs_are_byte_identical_to_lodforge_batch_and_share_its_state(tree):
    batch = subprocess.run([LODFORGE, "--quiet", "batch", str(tree / "in"), "-o", str(tree / "batch"), "--jobs", "2"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=False)
    assert batch.returncode == 0, batch.stdout
    dask = run_dask(tree / "in", tree / "dask")
    assert dask.returncode == 0, dask.stderr

    from_batch, from_dask = pack_files(tree / "batch"), pack_files(tree / "dask")
    assert len(from_batch) >= 2 * len(MESHES)  # a .glb and pack.json per asset at least
    assert sorted(from_batch) == sorted(from_dask)
    for name in from_batch:
        assert from_batch[name] == from_dask[name], name

    with open(tree / "dask" / "batch-report.json") as f:
        report = json.load(f)
    with open(tree / "batch" / "batch-report.json") as f:
        reference = json.load(f)
    assert report["format"] == "lodforge-batch-report"
    assert report["summary"]["ok"] == len(MESHES)
    assert report["jobs"] == 2
    for mine, theirs in zip(report["assets"], reference["assets"]):
        assert os.path.relpath(mine["output"], tree / "dask") == os.path.relpath(theirs["output"], tree / "batch")
        assert mine["levels"] == theirs["levels"]
        assert mine["bytes"] == theirs["bytes"] > 0
        assert mine["input_sha256"] == theirs["input_sha256"]

    # The Dask run's state file is the one `lodforge batch` reads: nothing left to do, for either.
    with open(tree / "dask" / "batch-state.json") as f:
        state = json.load(f)
    assert state["format"] == "lodforge-batch-state"
    assert len(state["assets"]) == len(MESHES)
    glb = next((tree / "dask" / "color").glob("*.glb"))
    stamp = glb.stat().st_mtime_ns
    batch = subprocess.run([LODFORGE, "--quiet", "batch", str(tree / "in"), "-o", str(tree / "dask")],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=False)
    assert batch.returncode == 0, batch.stdout
    assert "0 ok, 0 failed, %d skipped" % len(MESHES) in batch.stdout
    again = run_dask(tree / "in", tree / "dask")
    assert again.returncode == 0, again.stderr
    with open(tree / "dask" / "batch-report.json") as f:
        report = json.load(f)
    assert report["summary"]["skipped"] == len(MESHES)
    assert all(len(a["levels"]) >= 2 for a in report["assets"])  # a skipped asset keeps its levels
    assert glb.stat().st_mtime_ns == stamp


def test_dask_bad_asset_is_reported_and_retried(tree):
    (tree / "in" / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    first = run_dask(tree / "in", tree / "out")
    assert first.returncode == 1, first.stderr
    assert "1 of %d assets failed" % (len(MESHES) + 1) in first.stderr
    with open(tree / "out" / "batch-report.json") as f:
        report = json.load(f)
    broken = [a for a in report["assets"] if a["input"].endswith("broken.obj")]
    assert len(broken) == 1 and broken[0]["status"] == "failed"
    assert "broken.obj" in broken[0]["message"]
    assert report["summary"]["ok"] == len(MESHES)
    assert not (tree / "out" / "broken").exists()

    # Fixed, only the failed asset runs again.
    shutil.copyfile(os.path.join(SHARED, "seq-horse-gallop/0001.obj"), tree / "in" / "broken.obj")
    again = run_dask(tree / "in", tree / "out")
    assert again.returncode == 0, again.stderr
    with open(tree / "out" / "batch-report.json") as f:
        report = json.load(f)
    statuses = {os.path.basename(a["input"]): a["status"] for a in report["assets"]}
    assert statuses["broken.obj"] == "ok"
    assert statuses["color.ply"] == "skipped"


def test_bad_manifest_fails_with_its_name(tmp_path):
    manifest = tmp_path / "assets.json"
    manifest.write_text('[{"input": "a.ply", "lod": 2}]')
    done = run_dask(manifest, tmp_path / "out")
    assert done.returncode == 1
    assert str(manifest) in done.stderr and 'unknown key "lod"' in done.stderr

"""Shared fixtures: the CLI the results are checked against, and the shared meshes."""
import json
import os
import subprocess
from pathlib import Path

import pytest

SHARED = Path(os.environ.get("LODFORGE_SHARED_DATA", Path(__file__).resolve().parents[3] / "shared" / "data"))
LODFORGE = os.environ.get("LODFORGE_BIN", str(Path(__file__).resolve().parents[2] / "build" / "bin" / "lodforge"))
MESH_SUFFIXES = {".ply", ".obj", ".gltf", ".glb"}


def shared_meshes():
    """Every mesh file under the shared data directory, smallest first."""
    files = [p for p in SHARED.rglob("*") if p.suffix.lower() in MESH_SUFFIXES]
    return sorted(files, key=lambda p: (p.stat().st_size, str(p)))


def run_cli(*args, check=True):
    """Runs `lodforge ARGS` quietly; returns the completed process."""
    r = subprocess.run([LODFORGE, "--quiet", *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"lodforge {' '.join(map(str, args))} failed ({r.returncode}): {r.stderr}")
    return r


def cli_json(*args):
    return json.loads(run_cli(*args).stdout)


@pytest.fixture
def cli():
    return run_cli


@pytest.fixture
def bunny():
    return SHARED / "scan-bunny" / "bun_zipper.ply"


@pytest.fixture
def spot():
    return SHARED / "tex-spot" / "spot_triangulated.obj"

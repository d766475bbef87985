"""LodForge: level-of-detail authoring for heavy meshes, from Python.

Meshes are NumPy arrays (views into the core's buffers, no copies); the algorithms are the ones the
``lodforge`` command runs, with its defaults as keyword arguments. Long calls take ``progress``, a
callable ``progress(fraction, stage)``; returning ``False`` (or raising) cancels the work, which then
raises :class:`lodforge.Cancelled` (or the callable's exception). Errors of the core raise
:class:`lodforge.Error` with the core's message, which names the file. Tutorial: docs/python.md.
"""
from __future__ import annotations

import json as _json
import os as _os
from typing import Any, Dict, Union

# In a build tree the shipped presets sit in build/share/lodforge/presets, beside build/python/lodforge
# (the program-relative lookup of preset_library.h sees python3, not a LodForge program).
_build_presets = _os.path.join(_os.path.dirname(__file__), "..", "..", "share", "lodforge", "presets")
if "LODFORGE_PRESETS_DIR" not in _os.environ and _os.path.isdir(_build_presets):
    _os.environ["LODFORGE_PRESETS_DIR"] = _os.path.normpath(_build_presets)

from ._core import (  # noqa: E402
    HAVE_RENDER,
    Cancelled,
    Distance,
    Error,
    ImageError,
    LodChain,
    LodLevel,
    Material,
    Mesh,
    OneSidedDistance,
    SimplifyResult,
    ViewImageError,
    __version__,
    build_lod_chain,
    build_lodstrips,
    build_octree,
    compare,
    extract_lodstrips,
    extract_octree,
    octree_info,
    read_mesh,
    shipped_presets,
    simplify,
    write_lod_pack,
    write_mesh,
)
from . import _core  # noqa: E402

if HAVE_RENDER:
    from ._core import render_compare  # noqa: F401,E402

PathLike = Union[str, "_os.PathLike[str]"]


def mesh_info(mesh: Mesh, path: str = "") -> Dict[str, Any]:
    """The summary ``lodforge info --json`` prints for ``mesh`` (counts, attributes, bounds, findings)."""
    return _json.loads(_core._mesh_info_json(mesh, path))


def info(path: PathLike) -> Dict[str, Any]:
    """``lodforge info --json`` for a file: read without refusing defects, which are reported instead."""
    path = _os.fspath(path)
    return mesh_info(read_mesh(path, validate=False), path)


__all__ = [
    "HAVE_RENDER", "Cancelled", "Distance", "Error", "ImageError", "LodChain", "LodLevel", "Material", "Mesh",
    "OneSidedDistance", "SimplifyResult", "ViewImageError", "__version__", "build_lod_chain", "build_lodstrips",
    "build_octree", "compare", "extract_lodstrips", "extract_octree", "info", "mesh_info", "octree_info",
    "read_mesh", "shipped_presets", "simplify", "write_lod_pack", "write_mesh",
] + (["render_compare"] if HAVE_RENDER else [])

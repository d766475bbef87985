"""Type stubs of lodforge._core (the compiled extension); the package lodforge re-exports it."""
from __future__ import annotations

import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
HAVE_RENDER: bool

# progress(fraction in [0, 1], stage) -> None/True to go on, False to cancel.
Progress = Optional[Callable[[float, str], Optional[bool]]]
# A shipped preset's name, a .json file, or a dict in the preset format (docs/presets.md).
PresetArg = Union[None, str, "os.PathLike[str]", Dict[str, Any]]
# {"normal": 0.02, "color": 0.1, "uv": 0.1, "uv1": 0.4} or the CLI's "normal=0.02,uv1=0.4".
WeightsArg = Union[None, str, Dict[str, float]]
# A file or directory: str or any os.PathLike (pathlib.Path).
PathArg = Union[str, "os.PathLike[str]"]
F32 = npt.NDArray[np.float32]
U32 = npt.NDArray[np.uint32]

class Error(RuntimeError):
    """The core's error; str(e) names the file. kind: io, format, invalid, unsupported, argument, cancelled."""
    kind: str

class Cancelled(Error):
    """The progress callback returned False."""

class Material:
    name: str
    base_color: Tuple[float, float, float, float]
    metallic: float
    roughness: float
    double_sided: bool
    @property
    def base_color_texture(self) -> Dict[str, Any]: ...
    def __init__(self) -> None: ...

class Mesh:
    """Struct of arrays; the array properties are views (no copy) that keep the mesh alive."""
    positions: F32        # (n, 3)
    normals: F32          # (n, 3) or empty
    colors: F32           # (n, 4) RGBA in [0, 1] or empty
    texcoords: List[F32]  # one (n, 2) per set
    position_ids: U32     # (n,) or empty
    indices: U32          # (t, 3)
    face_materials: U32   # (t,) or empty
    materials: List[Material]
    source_dir: str
    @property
    def warnings(self) -> List[str]: ...
    @property
    def vertex_count(self) -> int: ...
    @property
    def point_count(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def bounds(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]: ...
    def __init__(self, positions: npt.ArrayLike = ..., indices: npt.ArrayLike = ...) -> None: ...
    def copy(self) -> Mesh: ...

def read_mesh(path: PathArg, *, validate: bool = True, place_every_instance: bool = False,
              progress: Progress = None) -> Mesh: ...
def write_mesh(mesh: Mesh, path: PathArg, *, ply_encoding: str = "binary", normals: bool = True, colors: bool = True,
               texcoords: bool = True, ply_colors_as_uchar: bool = True, progress: Progress = None) -> List[str]: ...
def _mesh_info_json(mesh: Mesh, path: str = "") -> str: ...
def shipped_presets() -> List[str]: ...

class SimplifyResult:
    mesh: Mesh
    triangles: int
    target_triangles: int
    dropped_faces: int
    error: float
    error_relative: float
    reason: str
    mode: str

def simplify(mesh: Mesh, *, ratio: Optional[float] = None, triangles: Optional[int] = None,
             max_error: Optional[float] = None, preset: PresetArg = None, weights: WeightsArg = None,
             lock_border: bool = False, mode: Optional[str] = None, area_weight: str = "area",
             height_weight: float = 0.0, placement: str = "optimal", progress: Progress = None) -> SimplifyResult: ...

class OneSidedDistance:
    max: float
    mean: float
    rms: float
    samples: int

class Distance:
    test_to_reference: OneSidedDistance
    reference_to_test: OneSidedDistance
    hausdorff: float
    mean: float
    rms: float
    diagonal: float
    hausdorff_relative: float
    mean_relative: float
    rms_relative: float
    color_rms: Optional[float]
    texcoord_rms: Optional[float]
    vertex_errors: F32
    region_errors: F32

def compare(reference: Mesh, test: Mesh, *, samples: int = 0, seed: int = 1, vertex_errors: bool = False,
            region_errors: bool = False, progress: Progress = None) -> Distance: ...

class ViewImageError:
    name: str
    mean_abs: float
    over_threshold: float
    silhouette: float
    covered: int

class ImageError:
    views: List[ViewImageError]
    mean_abs: float
    over_threshold: float
    silhouette: float
    size: int
    threshold: int
    files: List[str]

def render_compare(reference: Mesh, test: Mesh, *, size: int = 256, threshold: int = 32,
                   output_dir: PathArg = "") -> ImageError: ...  # only when HAVE_RENDER

class LodLevel:
    mesh: Mesh
    triangles: int
    target_triangles: int
    reason: str
    step_error: float
    step_error_relative: float
    accumulated_error: float
    accumulated_error_relative: float
    distance: Optional[Distance]
    input_vertex: U32

class LodChain:
    levels: List[LodLevel]
    shared: Mesh
    shared_ranges: List[Tuple[int, int, int]]

def build_lod_chain(mesh: Mesh, *, levels: Optional[Sequence[float]] = None,
                    level_triangles: Optional[Sequence[int]] = None, level_errors: Optional[Sequence[float]] = None,
                    preset: PresetArg = None, weights: WeightsArg = None, lock_border: bool = False,
                    measure: bool = True, samples: int = 0, progress: Progress = None) -> LodChain: ...

def write_lod_pack(mesh: Union[Mesh, PathArg], output_dir: PathArg, *, preset: PresetArg = None,
                   source_path: Optional[PathArg] = None, method: Optional[str] = None,
                   levels: Optional[Sequence[float]] = None, level_triangles: Optional[Sequence[float]] = None,
                   level_errors: Optional[Sequence[float]] = None, weights: WeightsArg = None,
                   lock_border: bool = False, image_error: bool = False, progress: Progress = None) -> Dict[str, Any]: ...

def build_octree(input_ply: PathArg, asset_path: PathArg, *, preset: PresetArg = None, max_triangles: Optional[int] = None,
                 max_depth: Optional[int] = None, memory_mb: Optional[int] = None, temp_dir: PathArg = "",
                 weights: WeightsArg = None, threads: int = 2, progress: Progress = None) -> Dict[str, Any]: ...
# The keys and values of `lodforge octree info --json` (build_octree: the same plus 'warnings').
def octree_info(asset_path: PathArg) -> Dict[str, Any]: ...
def extract_octree(asset_path: PathArg, *, level: Optional[int] = None, camera: Optional[Sequence[float]] = None,
                   screen_error: Optional[float] = None, viewport: Tuple[int, int] = (1920, 1080),
                   culling: bool = True, progress: Progress = None) -> Mesh: ...

def build_lodstrips(mesh: Mesh, path: PathArg, *, preset: PresetArg = None, coarsest: Optional[float] = None,
                    degenerate: bool = False, weights: WeightsArg = None, lock_border: bool = False,
                    max_strip_length: int = 256, strip_order: str = "run-off",
                    progress: Progress = None) -> Dict[str, Any]: ...
def extract_lodstrips(path: PathArg, *, lod: float = 1.0, triangles: Optional[int] = None) -> Mesh: ...

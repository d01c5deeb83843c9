"""Type stubs of `import vmas` (apps/python/vmas_module.cpp)."""

import os
import sys
from typing import Any, Callable, Optional, TypedDict, Union

if sys.version_info >= (3, 11):
    from typing import Unpack
else:
    from typing_extensions import Unpack

import numpy as np
import numpy.typing as npt

__version__: str

class Error(Exception): ...
class InvalidInput(ValueError): ...
class InvalidOption(ValueError): ...
class InvalidArgument(ValueError): ...
class IoError(OSError): ...
class Cancelled(Exception): ...

class RunOptions(TypedDict, total=False):
    """The keyword options of skeletonize(), Skeletonizer() and EditSession(): the options of
    `vmas skeletonize --help` with '_' for '-' (vmas.options() lists them with their defaults
    and ranges; tests/python/test_options.py checks this list against it)."""
    max_spheres: int
    lambda_: float
    final_lambda: float
    final_rounds: int
    refine_moves: int
    refine_min_gain: float
    k: int
    normal_k: int
    max_points: int
    estimate_normals: bool
    keep_strays: bool
    no_mesh_sampling: bool
    density: Union[npt.ArrayLike, str, os.PathLike[str]]  # values per row, a rule, or a file
    denoise: Union[str, float, bool]  # "auto", "off", 0.005, "0.5%"; True: auto, False: off
    orient_normals: bool
    no_projection: bool
    keep_cavities: bool
    keep_loops: bool
    no_coarse_start: bool
    max_iterations: int
    convergence: float
    split_interval: int
    splits_per_round: int
    denoise_angle: float
    ball_tolerance: float
    starts: int

class Surface:
    """A shape as vmas reads it."""
    @property
    def points(self) -> npt.NDArray[np.float64]: ...  # (N, 3)
    @property
    def normals(self) -> Optional[npt.NDArray[np.float64]]: ...  # (N, 3)
    @property
    def faces(self) -> Optional[npt.NDArray[np.int32]]: ...  # (F, 3)
    @property
    def density(self) -> Optional[npt.NDArray[np.float64]]: ...  # (N,)

class MedialMesh:
    @property
    def centers(self) -> npt.NDArray[np.float64]: ...  # (M, 3)
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...  # (M,)
    @property
    def edges(self) -> npt.NDArray[np.int32]: ...  # (E, 2)
    @property
    def faces(self) -> npt.NDArray[np.int32]: ...  # (T, 3)

class Result:
    @property
    def medial_mesh(self) -> MedialMesh: ...
    @property
    def centers(self) -> npt.NDArray[np.float64]: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def edges(self) -> npt.NDArray[np.int32]: ...
    @property
    def faces(self) -> npt.NDArray[np.int32]: ...
    @property
    def labels(self) -> npt.NDArray[np.int32]: ...  # (N,), -1 for a dropped point
    @property
    def warnings(self) -> list[tuple[str, str]]: ...  # (code, message)
    @property
    def summary(self) -> dict[str, Any]: ...  # as `vmas skeletonize --json` gives it
    @property
    def seconds(self) -> dict[str, float]: ...
    def to_dict(self) -> dict[str, Any]: ...

MedialLike = Union[Result, MedialMesh, Any]  # anything with centers, radii, edges, faces

class Skeletonizer:
    """The optimisation step by step, editable between steps."""
    def __init__(self, points: Union[npt.ArrayLike, Surface],
                 normals: Optional[npt.ArrayLike] = None,
                 faces: Optional[npt.ArrayLike] = None, *,
                 spheres: Optional[int] = None, error: Optional[float] = None,
                 threads: int = 0, **options: Unpack[RunOptions]) -> None: ...
    def step(self) -> float: ...
    def advance(self) -> dict[str, Any]: ...
    def run(self, progress: Optional[Callable[[str, float], Optional[bool]]] = None
            ) -> dict[str, Any]: ...
    def finish(self, progress: Optional[Callable[[str, float], Optional[bool]]] = None
               ) -> dict[str, Any]: ...  # refits, refinement, measured error: as skeletonize
    def split(self) -> int: ...
    def add_sphere(self, vertex: int) -> int: ...
    def remove_sphere(self, id: int) -> None: ...
    def freeze(self, id: int, frozen: bool = True) -> None: ...
    def medial_mesh(self) -> MedialMesh: ...
    @property
    def points(self) -> npt.NDArray[np.float64]: ...  # prepared vertices, input's coordinates
    @property
    def vertex_labels(self) -> npt.NDArray[np.int32]: ...  # one per row of points
    @property
    def labels(self) -> npt.NDArray[np.int32]: ...  # one per input row, -1: dropped
    @property
    def keys(self) -> npt.NDArray[np.uint64]: ...
    @property
    def total_error(self) -> float: ...
    @property
    def spheres(self) -> int: ...

class EditSession:
    """The optimisation in a worker thread while you edit it (any thread may call)."""
    def __init__(self, points: Union[npt.ArrayLike, Surface],
                 normals: Optional[npt.ArrayLike] = None,
                 faces: Optional[npt.ArrayLike] = None, *,
                 spheres: Optional[int] = None, error: Optional[float] = None,
                 threads: int = 0, **options: Unpack[RunOptions]) -> None: ...
    def remove(self, key: int) -> None: ...
    def split_at(self, vertex: int) -> None: ...
    def freeze(self, key: int, frozen: bool = True) -> None: ...
    def set_target_spheres(self, count: int) -> None: ...
    def set_lambda(self, lambda_: float) -> None: ...
    def paint_density(self, vertex: int, radius: float, amount: float) -> None: ...
    def set_density(self, density: Optional[npt.ArrayLike]) -> None: ...
    def undo(self) -> None: ...
    def redo(self) -> None: ...
    def pause(self, paused: bool = True) -> None: ...
    def finish(self) -> None: ...
    def cancel_finish(self) -> None: ...
    def wait(self, version: int = 0, timeout: float = 1.0) -> int: ...
    def snapshot(self) -> dict[str, Any]: ...
    def close(self) -> None: ...
    def __enter__(self) -> "EditSession": ...
    def __exit__(self, *args: Any) -> None: ...

def skeletonize(points: Union[npt.ArrayLike, Surface],
                normals: Optional[npt.ArrayLike] = None,
                faces: Optional[npt.ArrayLike] = None, *,
                spheres: Optional[int] = None,
                error: Optional[float] = None,
                threads: int = 0,
                progress: Optional[Callable[[str, float], Optional[bool]]] = None,
                **options: Unpack[RunOptions]) -> Result: ...
def options() -> list[dict[str, Any]]: ...  # flag, short, keyword, field, type, default, range, help
def read(path: str, *, density_field: Optional[str] = None) -> Surface: ...
def density_by_rule(points: Union[npt.ArrayLike, Surface], rule: str) -> npt.NDArray[np.float64]: ...
def read_medial(path: str) -> MedialMesh: ...
def write(path: str, medial: MedialLike) -> None: ...
def evaluate(shape: Union[Surface, npt.ArrayLike], medial: MedialLike,
             faces: Optional[npt.ArrayLike] = None) -> dict[str, float]: ...

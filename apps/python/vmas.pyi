"""Type stubs of `import vmas` (apps/python/vmas_module.cpp)."""

from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str

class Error(Exception): ...
class InvalidInput(ValueError): ...
class InvalidOption(ValueError): ...
class InvalidArgument(ValueError): ...
class IoError(OSError): ...
class Cancelled(Exception): ...

class Surface:
    """A shape as vmas reads it."""
    @property
    def points(self) -> npt.NDArray[np.float64]: ...  # (N, 3)
    @property
    def normals(self) -> Optional[npt.NDArray[np.float64]]: ...  # (N, 3)
    @property
    def faces(self) -> Optional[npt.NDArray[np.int32]]: ...  # (F, 3)

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
                 threads: int = 0, **options: Any) -> None: ...
    def step(self) -> float: ...
    def advance(self) -> dict[str, Any]: ...
    def run(self, progress: Optional[Callable[[str, float], Optional[bool]]] = None
            ) -> dict[str, Any]: ...
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

def skeletonize(points: Union[npt.ArrayLike, Surface],
                normals: Optional[npt.ArrayLike] = None,
                faces: Optional[npt.ArrayLike] = None, *,
                spheres: Optional[int] = None,
                error: Optional[float] = None,
                threads: int = 0,
                progress: Optional[Callable[[str, float], Optional[bool]]] = None,
                **options: Any) -> Result: ...
def read(path: str) -> Surface: ...
def read_medial(path: str) -> MedialMesh: ...
def write(path: str, medial: MedialLike) -> None: ...
def evaluate(shape: Union[Surface, npt.ArrayLike], medial: MedialLike,
             faces: Optional[npt.ArrayLike] = None) -> dict[str, float]: ...

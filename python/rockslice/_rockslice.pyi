# Types of the extension rockslice._rockslice (python/src/*.cpp) for editors and type checkers.
from os import PathLike
from typing import Any, Callable, Optional, Union

import numpy as np
import numpy.typing as npt

__version__: str
BOUNDARY: int
REMOVED: int
FIXED: int
YADE_INITIAL_GAP: float

Progress = Optional[Callable[[str, int, int], Any]]

class Error(ValueError):
    where: str
    problem: str
    fix: str

class Model:
    stage: str  # 'joints', 'blocks', 'pruned' or 'geometry'
    name: str
    seed: int
    dimension: int
    length_scale: float
    pruned: bool
    provenance: dict[str, str]
    # per block
    flags: npt.NDArray[np.uint8]
    cluster: npt.NDArray[np.int64]
    inradius: npt.NDArray[np.float64]
    origin: npt.NDArray[np.float64]
    bsphere: npt.NDArray[np.float64]
    fixed: npt.NDArray[np.bool_]
    volume: npt.NDArray[np.float64]
    centroid: npt.NDArray[np.float64]
    inertia: npt.NDArray[np.float64]
    # per face
    face_offset: npt.NDArray[np.int64]
    face_normal: npt.NDArray[np.float64]
    face_d: npt.NDArray[np.float64]
    face_joint: npt.NDArray[np.int64]
    face_area: npt.NDArray[np.float64]
    face_joint_fraction: npt.NDArray[np.float64]
    # vertices and face loops
    vertex_offset: npt.NDArray[np.int64]
    vertices: npt.NDArray[np.float64]
    face_vertex_offset: npt.NDArray[np.int64]
    face_vertices: npt.NDArray[np.int64]
    # block shape factors: alpha, beta, beta_k, class, class_kalenchuk (docs/block-shape.md)
    shape: dict[str, npt.NDArray[Any]]
    # /stability and /contacts (rockslice.stability, slice-stability; docs/stability.md)
    stability: Optional[dict[str, npt.NDArray[Any]]]
    contacts: Optional[dict[str, npt.NDArray[Any]]]
    # joints and sets
    joint_count: int
    joint_normal: npt.NDArray[np.float64]
    joint_d: npt.NDArray[np.float64]
    joint_centre: npt.NDArray[np.float64]
    joint_dip: npt.NDArray[np.float64]
    joint_dip_direction: npt.NDArray[np.float64]
    joint_kind: npt.NDArray[np.uint8]
    joint_set: npt.NDArray[np.int32]
    joint_friction_angle: npt.NDArray[np.float64]
    joint_cohesion: npt.NDArray[np.float64]
    joint_tension: npt.NDArray[np.float64]
    joint_polygons: tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]
    sets: dict[str, Any]
    def __len__(self) -> int: ...
    def friction_deg(self, default: float = 30.0) -> npt.NDArray[np.float64]: ...
    def with_joints(self, index: npt.ArrayLike) -> Model: ...
    def save(self, path: Union[str, PathLike[str]], compress: bool = False,
             provenance: Optional[dict[str, str]] = None) -> None: ...

def load(path: Union[str, PathLike[str]]) -> Model: ...

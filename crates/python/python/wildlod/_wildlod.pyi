"""Type stubs of the native module (wildlod._wildlod)."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike[str]]

__version__: str

def _simplify(
    positions: npt.NDArray[np.float32],
    indices: npt.NDArray[np.uint32],
    face_sizes: npt.NDArray[np.uint32],
    *,
    ratio: Optional[float] = ...,
    faces_target: Optional[int] = ...,
    error: Optional[float] = ...,
    uvs: Optional[npt.NDArray[np.float32]] = ...,
    normals: Optional[npt.NDArray[np.float32]] = ...,
    colors: Optional[npt.NDArray[np.float32]] = ...,
    joints: Optional[npt.NDArray[np.uint16]] = ...,
    weights: Optional[npt.NDArray[np.float32]] = ...,
    vertex_weights: Optional[npt.NDArray[np.float32]] = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def simplify_file(
    src: _Path,
    dst: _Path,
    *,
    ratio: Optional[float] = ...,
    faces_target: Optional[int] = ...,
    error: Optional[float] = ...,
    per_mesh: bool = ...,
    textures: str = ...,
    texture_size: Optional[int] = ...,
    normal_bake: bool = ...,
    overwrite: bool = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def lod_chain(
    src: _Path,
    dst: _Path,
    *,
    ratios: Optional[Sequence[float]] = ...,
    errors: Optional[Sequence[float]] = ...,
    faces_targets: Optional[Sequence[int]] = ...,
    textures: str = ...,
    texture_size: Optional[int] = ...,
    normal_bake: bool = ...,
    split: bool = ...,
    overwrite: bool = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def info(path: _Path) -> Dict[str, Any]: ...
def compare(
    reference: _Path,
    candidate: _Path,
    *,
    samples: int = ...,
    texture_samples: int = ...,
    seed: Optional[int] = ...,
    animation: Optional[int] = ...,
    frames: int = ...,
    fps: float = ...,
) -> Dict[str, Any]: ...
def batch(
    src_dir: _Path,
    dst_dir: _Path,
    *,
    ratio: Optional[float] = ...,
    faces_target: Optional[int] = ...,
    error: Optional[float] = ...,
    lod_ratios: Optional[Sequence[float]] = ...,
    lod_errors: Optional[Sequence[float]] = ...,
    lod_faces_targets: Optional[Sequence[int]] = ...,
    split: bool = ...,
    per_mesh: bool = ...,
    textures: str = ...,
    texture_size: Optional[int] = ...,
    normal_bake: bool = ...,
    format: Optional[str] = ...,
    jobs: Optional[int] = ...,
    skip_existing: bool = ...,
    summary: Optional[_Path] = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def report(
    reference: _Path,
    candidate: _Path,
    output: _Path,
    *,
    samples: int = ...,
    overwrite: bool = ...,
) -> Dict[str, Any]: ...
def option_names() -> List[str]: ...

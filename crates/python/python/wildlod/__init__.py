"""wildlod: levels of detail for real-world meshes.

Simplify numpy arrays (triangles or polygons, with UVs, normals, colors
and skin weights) or whole mesh files (glTF, GLB, OBJ, PLY, STL), make
chains of levels of detail, describe and compare files. The work runs in
Rust without the GIL, so threads simplify at once.

>>> import numpy as np, wildlod
>>> out = wildlod.simplify(positions, faces, ratio=0.25)        # doctest: +SKIP
>>> out["positions"], out["faces"], out["report"]["error"]      # doctest: +SKIP

The report dicts have the keys of the command line's ``--json`` output
(docs/cli.md): ``simplify_file`` those of ``wildlod simplify --json``,
``lod_chain`` those of ``wildlod lod --json``, ``info`` those of
``wildlod info --json``, ``compare`` those of ``wildlod compare --json``,
``batch`` those of ``wildlod batch --json`` (and ``wildlod-summary.json``)
and ``report`` those of ``wildlod report --json``; file functions add
``warnings``.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np

from ._errors import WildlodError, WildlodOSError
from ._wildlod import (
    __version__,
    batch,
    compare,
    info,
    lod_chain,
    option_names,
    report,
    simplify_file,
)
from ._wildlod import _simplify

__all__ = [
    "WildlodError",
    "WildlodOSError",
    "__version__",
    "batch",
    "compare",
    "info",
    "lod_chain",
    "option_names",
    "report",
    "simplify",
    "simplify_file",
]

Faces = Union[np.ndarray, Sequence[Sequence[int]]]


def _faces_in(faces: Faces, face_sizes: Optional[Any]):
    """(indices, sizes, kind): the faces as a flat uint32 index array and
    one size per face, and the form to give them back in."""
    if face_sizes is not None:
        indices = np.asarray(faces)
        sizes = np.asarray(face_sizes)
        if indices.ndim != 1:
            raise WildlodError(
                f"with face_sizes, faces must be a flat index array, got shape {indices.shape}"
            )
        return _indices(indices, "faces"), _indices(sizes, "face_sizes"), "flat"
    if isinstance(faces, np.ndarray):
        if faces.ndim != 2 or faces.shape[1] < 3:
            raise WildlodError(
                f"faces has shape {faces.shape}: give an (n, 3) array of triangles, an (n, k) "
                "array of k-gons, a list of lists, or a flat array with face_sizes"
            )
        n, k = faces.shape
        return _indices(faces.reshape(-1), "faces"), np.full(n, k, dtype=np.uint32), "array"
    # A list of lists (polygons of any sizes).
    rows = [list(f) for f in faces]
    sizes = np.array([len(r) for r in rows], dtype=np.int64)
    flat = np.array([i for r in rows for i in r], dtype=np.int64)
    return _indices(flat, "faces"), _indices(sizes, "face sizes"), "lists"


def _indices(a: np.ndarray, name: str) -> np.ndarray:
    """Non-negative integers as uint32, refusing floats and negatives by
    name rather than wrapping them around."""
    a = np.asarray(a)
    if a.size == 0:
        return np.zeros(0, dtype=np.uint32)
    if not np.issubdtype(a.dtype, np.integer):
        raise WildlodError(f"{name} must be integers, got dtype {a.dtype}")
    lo, hi = int(a.min()), int(a.max())
    if lo < 0:
        raise WildlodError(f"{name} has a negative entry {lo} at position {int(np.argmin(a))}")
    if hi > np.iinfo(np.uint32).max:
        raise WildlodError(f"{name} has entry {hi}, beyond 32-bit indices")
    return np.ascontiguousarray(a, dtype=np.uint32)


def _floats(a: Optional[Any], name: str, cols: Sequence[int]) -> Optional[np.ndarray]:
    if a is None:
        return None
    a = np.ascontiguousarray(a, dtype=np.float32)
    if a.ndim != 2 or a.shape[1] not in cols:
        want = " or ".join(f"(n, {c})" for c in cols)
        raise WildlodError(f"{name} has shape {a.shape}, expected {want}")
    return a


def simplify(
    positions: Any,
    faces: Faces,
    *,
    face_sizes: Optional[Any] = None,
    ratio: Optional[float] = None,
    faces_target: Optional[int] = None,
    error: Optional[float] = None,
    uvs: Optional[Any] = None,
    normals: Optional[Any] = None,
    colors: Optional[Any] = None,
    joints: Optional[Any] = None,
    weights: Optional[Any] = None,
    vertex_weights: Optional[Any] = None,
    **options: Any,
) -> Dict[str, Any]:
    """Simplify a mesh given as arrays.

    positions: (n, 3) floats. faces: an (m, 3) integer array of triangles
    (or (m, k) of k-gons), a list of lists of vertex indices (polygons of
    any size), or a flat index array with ``face_sizes``. Quads and
    polygons are kept where the simplifier can (Knodt 2024's ordering).

    Targets, the first reached stops (none: ``ratio=0.5``): ``ratio`` of
    the triangles (a quad counts as two), ``faces_target`` triangles, or
    ``error`` as a fraction of the bounding-box diagonal.

    Per-vertex streams, fitted through every collapse and returned the
    same way: ``uvs`` (n, 2), ``normals`` (n, 3), ``colors`` (n, 3 or 4),
    skin ``joints`` (n, k) integers with ``weights`` (n, k). A vertex whose
    corners end up with different values (a UV seam) is split, as glTF
    does. ``vertex_weights`` (n,) makes collapses near heavy vertices cost
    more (1 is neutral).

    ``options`` are the CLI's tuning flags with underscores
    (``virtual_radius``, ``keep_topology``, ``lock_borders``,
    ``max_normal_turn``, ``no_quads``, ``quad_epsilon``, ``quad_tie_factor``,
    ``quad_tolerance``,
    ``tangent_weight``,
    ``symmetry``, ``area_floor``,
    ``pinch_cost``, ``pinch_distance``, ``area_exponent``, ``face_weight_floor``,
    ``crease_weight``, ``crease_angle``, ``crease_area_weight``, ``current_faces``,
    ``refit_sweeps``, ``keep_hidden_twins``, ``keep_enclosed_parts``, ``no_layers``, ``classic``, ``uv_weight``, ``normal_weight``,
    ``color_weight``, ``skin_weight``, ``seams`` = 'penalize' | 'keep' |
    'ignore', ``seam_weight``, ``normals`` is the stream here, so the
    normal mode is ``normal_mode`` = 'fit' | 'recompute'); see
    ``wildlod.option_names()``.

    Returns a dict: ``positions`` (n', 3) float32, ``faces`` in the form
    given (an (m', k) array, a list of lists, or the flat array),
    ``indices`` and ``face_sizes`` (flat, always), the streams given, and
    ``report`` (``input_triangles``, ``target_triangles``,
    ``output_triangles``, ``error``, ``stop``, ``collapses``, ``seconds``…).

    Raises WildlodError (a ValueError) for bad arrays or settings, and
    TypeError for an unknown option.
    """
    indices, sizes, kind = _faces_in(faces, face_sizes)
    pos = _floats(positions, "positions", [3])
    if joints is not None:
        joints = np.asarray(joints)
        if joints.ndim != 2:
            raise WildlodError(f"joints has shape {joints.shape}, expected (n, k)")
        if joints.size and (not np.issubdtype(joints.dtype, np.integer) or joints.min() < 0
                            or joints.max() > np.iinfo(np.uint16).max):
            raise WildlodError("joints must be integers from 0 to 65535")
        joints = np.ascontiguousarray(joints, dtype=np.uint16)
    if weights is not None:
        weights = np.ascontiguousarray(weights, dtype=np.float32)
        if weights.ndim != 2:
            raise WildlodError(f"weights has shape {weights.shape}, expected (n, k)")
    vw = None
    if vertex_weights is not None:
        vw = np.ascontiguousarray(vertex_weights, dtype=np.float32).reshape(-1)
    out = _simplify(
        pos,
        indices,
        sizes,
        ratio=ratio,
        faces_target=faces_target,
        error=error,
        uvs=_floats(uvs, "uvs", [2]),
        normals=_floats(normals, "normals", [3]),
        colors=_floats(colors, "colors", [3, 4]),
        joints=joints,
        weights=weights,
        vertex_weights=vw,
        **options,
    )
    flat, out_sizes = out["indices"], out["face_sizes"]
    if kind == "flat":
        out["faces"] = flat
    elif kind == "array" and out_sizes.size and np.all(out_sizes == out_sizes[0]):
        out["faces"] = flat.reshape(-1, int(out_sizes[0]))
    elif kind == "array" and out_sizes.size == 0:
        out["faces"] = flat.reshape(0, 3)
    else:
        # Mixed sizes (quads and triangles from an array of quads): lists.
        ends = np.cumsum(out_sizes)
        out["faces"] = [flat[e - k:e].tolist() for e, k in zip(ends, out_sizes)]
    return out

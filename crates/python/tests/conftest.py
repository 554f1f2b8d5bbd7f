"""Shared helpers: meshes generated in numpy, OBJ files written by hand
(independent of wildlod's writers), and the CLI binary for comparing keys."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

IN_CI = os.environ.get("CI") == "true"
REPO = Path(__file__).resolve().parents[3]


def torus(n=48, m=24, big=1.0, small=0.35, quads=False):
    """A torus of n*m quads (or 2*n*m triangles), with UVs and normals per
    vertex; the seam rows are welded, so it is closed."""
    u = np.arange(n) / n * 2 * np.pi
    v = np.arange(m) / m * 2 * np.pi
    uu, vv = np.meshgrid(u, v, indexing="ij")
    x = (big + small * np.cos(vv)) * np.cos(uu)
    y = (big + small * np.cos(vv)) * np.sin(uu)
    z = small * np.sin(vv)
    pos = np.stack([x, y, z], -1).reshape(-1, 3)
    normals = np.stack([np.cos(vv) * np.cos(uu), np.cos(vv) * np.sin(uu), np.sin(vv)], -1).reshape(-1, 3)
    uvs = np.stack([uu / (2 * np.pi), vv / (2 * np.pi)], -1).reshape(-1, 2)
    idx = lambda i, j: (i % n) * m + (j % m)  # noqa: E731
    q = np.array([[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]
                  for i in range(n) for j in range(m)])
    faces = q if quads else np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    return pos, faces, uvs, normals


def grid(n=20):
    """An open n*n grid of quads in the z = 0 plane, bumped a little."""
    xs, ys = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    pos = np.stack([xs.ravel(), ys.ravel(), 0.05 * np.sin(xs.ravel() * 0.7) * np.cos(ys.ravel())], 1)
    q = []
    for i in range(n):
        for j in range(n):
            a = i * (n + 1) + j
            q.append([a, a + n + 1, a + n + 2, a + 1])
    return pos.astype(np.float64), np.array(q)


def write_obj(path, pos, faces):
    """A plain OBJ file (1-based indices)."""
    with open(path, "w") as f:
        for p in pos:
            f.write(f"v {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}\n")
        for face in faces:
            f.write("f " + " ".join(str(int(i) + 1) for i in face) + "\n")
    return Path(path)


@pytest.fixture
def torus_obj(tmp_path):
    pos, faces, _, _ = torus()
    return write_obj(tmp_path / "torus.obj", pos, faces)


def cli_binary():
    """The wildlod binary that `cargo test --workspace --release` built, or
    None outside CI when it has not been built (a failure in CI)."""
    for p in [os.environ.get("WILDLOD_BIN"), REPO / "target" / "release" / "wildlod",
              shutil.which("wildlod")]:
        if p and Path(p).is_file():
            return str(p)
    if IN_CI:
        pytest.fail("the wildlod binary is not built (cargo build --release -p wildlod-cli)")
    pytest.skip("SKIPPED: the wildlod binary is not built; its keys are not compared")

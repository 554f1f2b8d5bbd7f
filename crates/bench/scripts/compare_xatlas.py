"""Our atlas layout against xatlas (the library Godot and Filament use), on
the same simplified meshes: charts, L2 stretch (Sander et al. 2001,
normalized: 1 is an isometry), angle distortion (area-weighted ratio of
singular values), atlas use (texel centers inside a chart) and layout time.

Our side is read from baked LODs (`wildlod simplify --bake`: TEXCOORD_0 of
every primitive is one atlas) with the layout time the CLI prints; xatlas
(PyPI package `xatlas`, xatlas 2022+) lays out the same triangles at the same
resolution with the same padding (4 texels), one atlas.

usage: python compare_xatlas.py SIZE baked1.glb [baked2.glb …]
(needs numpy, trimesh and xatlas: `pip install xatlas trimesh` in a venv)
"""
import sys
import time

import numpy as np
import trimesh
import xatlas


def stats(v, f, uv, size):
    p = v[f]
    q = uv[f] * size
    a3 = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    a2 = 0.5 * ((q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1])
                - (q[:, 1, 1] - q[:, 0, 1]) * (q[:, 2, 0] - q[:, 0, 0]))
    ok = (a3 > 0) & (np.abs(a2) > 0)
    p, q, a3, a2 = p[ok], q[ok], a3[ok], a2[ok]
    ss = (p[:, 0] * (q[:, 1, 1] - q[:, 2, 1])[:, None] + p[:, 1] * (q[:, 2, 1] - q[:, 0, 1])[:, None]
          + p[:, 2] * (q[:, 0, 1] - q[:, 1, 1])[:, None]) / (2 * a2[:, None])
    st = (p[:, 0] * (q[:, 2, 0] - q[:, 1, 0])[:, None] + p[:, 1] * (q[:, 0, 0] - q[:, 2, 0])[:, None]
          + p[:, 2] * (q[:, 1, 0] - q[:, 0, 0])[:, None]) / (2 * a2[:, None])
    a, b, c = (ss * ss).sum(1), (ss * st).sum(1), (st * st).sum(1)
    root = np.sqrt((a - c) ** 2 + 4 * b * b)
    big, small = np.sqrt(0.5 * (a + c + root)), np.sqrt(np.maximum(0.5 * (a + c - root), 0))
    l2 = np.sqrt((a3 * 0.5 * (a + c)).sum() / a3.sum()) * np.sqrt(np.abs(a2).sum() / a3.sum())
    angle = (a3 * np.where(small > 0, big / np.maximum(small, 1e-30), 1e6)).sum() / a3.sum()
    # Texel centers inside some triangle.
    covered = np.zeros((size, size), bool)
    for t in uv[f] * size:
        lo = np.floor(t.min(0) - 0.5).astype(int).clip(0, size - 1)
        hi = np.ceil(t.max(0) + 0.5).astype(int).clip(0, size)
        xs, ys = np.meshgrid(np.arange(lo[0], hi[0]) + 0.5, np.arange(lo[1], hi[1]) + 0.5)
        def edge(a, b):
            return (b[0] - a[0]) * (ys - a[1]) - (b[1] - a[1]) * (xs - a[0])
        e0, e1, e2 = edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])
        inside = ((e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | ((e0 <= 0) & (e1 <= 0) & (e2 <= 0))
        covered[lo[1]:hi[1], lo[0]:hi[0]] |= inside
    return l2, angle, covered.mean()


def main():
    size = int(sys.argv[1])
    print('| file | primitive | triangles | ours: charts | stretch | angle | use | xatlas: charts | stretch | angle | use | xatlas s |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|')
    for path in sys.argv[2:]:
        scene = trimesh.load(path, force='scene', process=False)
        for name, g in scene.geometry.items():
            uv = getattr(g.visual, 'uv', None)
            if uv is None:
                continue
            v = np.asarray(g.vertices, np.float64)
            f = np.asarray(g.faces, np.int64)
            ours = stats(v, f, np.asarray(uv, np.float64), size)
            # Our charts: connected components of the UV layout.
            keys = {}
            parent = list(range(len(v)))
            def find(i):
                while parent[i] != i:
                    parent[i] = parent[parent[i]]
                    i = parent[i]
                return i
            for t in f:
                for k in range(3):
                    parent[find(t[k])] = find(t[(k + 1) % 3])
            ours_charts = len({find(i) for i in np.unique(f)})
            atlas = xatlas.Atlas()
            atlas.add_mesh(v.astype(np.float32), f.astype(np.uint32))
            po = xatlas.PackOptions()
            po.resolution = size
            po.padding = 4
            t0 = time.perf_counter()
            atlas.generate(xatlas.ChartOptions(), po)
            secs = time.perf_counter() - t0
            vmap, xf, xuv = atlas[0] if hasattr(atlas, '__getitem__') else atlas.get_mesh(0)
            xs = stats(v[vmap], xf.astype(np.int64), np.asarray(xuv, np.float64), size)
            print(f'| {path.rsplit("/", 1)[-1]} | {name} | {len(f)} | {ours_charts} | {ours[0]:.3f} | {ours[1]:.3f} | '
                  f'{100 * ours[2]:.0f}% | {atlas.chart_count} (atlases {atlas.atlas_count}) | {xs[0]:.3f} | '
                  f'{xs[1]:.3f} | {100 * xs[2]:.0f}% | {secs:.3f} |', flush=True)


main()

"""wildlod with trimesh: simplify a trimesh.Trimesh and get one back, with
its UVs, and make a chain of levels of detail from any file trimesh reads.

    python examples/trimesh_lod.py model.obj 0.5 0.25 0.1
"""

import sys

import numpy as np
import trimesh

import wildlod


def simplify_trimesh(mesh: trimesh.Trimesh, ratio: float, **options) -> trimesh.Trimesh:
    """A simplified copy of ``mesh``: positions and faces through
    ``wildlod.simplify``, UVs too when the mesh has them (trimesh keeps one
    UV per vertex, as wildlod returns them)."""
    uv = getattr(mesh.visual, "uv", None)
    out = wildlod.simplify(mesh.vertices, mesh.faces, ratio=ratio, uvs=uv, **options)
    visual = None
    if uv is not None:
        visual = trimesh.visual.TextureVisuals(uv=out["uvs"], material=mesh.visual.material)
    lod = trimesh.Trimesh(out["positions"], out["faces"], visual=visual, process=False)
    lod.metadata["wildlod"] = out["report"]
    return lod


def lod_chain(mesh: trimesh.Trimesh, ratios, **options):
    """Levels of detail, each simplified from the one before (ratios of the
    input, finest first)."""
    levels, current = [mesh], mesh
    for r in ratios:
        current = simplify_trimesh(current, r * len(mesh.faces) / len(current.faces), **options)
        levels.append(current)
    return levels


def main(argv):
    mesh = trimesh.load(argv[1], force="mesh")
    ratios = [float(r) for r in argv[2:]] or [0.5, 0.25, 0.1]
    for k, lod in enumerate(lod_chain(mesh, ratios)):
        report = lod.metadata.get("wildlod", {})
        print(f"lod{k}: {len(lod.faces)} triangles, watertight {lod.is_watertight}, "
              f"error {report.get('error', 0.0):.4f}")


if __name__ == "__main__":
    main(sys.argv)

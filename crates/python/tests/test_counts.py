"""Issue 34: one triangle count for instanced meshes. The truck's wheel mesh
is drawn by two nodes; info, simplify_file, lod_chain and batch all count
the triangles drawn, as the CLI does."""

import os
import shutil
from pathlib import Path

import pytest

import wildlod

CORPUS = Path(os.environ.get("WILDLOD_CORPUS",
                             Path(__file__).resolve().parents[4] / "shared" / "corpus"))
TRUCK = CORPUS / "textured" / "CesiumMilkTruck.glb"

if not TRUCK.is_file():
    if os.environ.get("CI") == "true":
        raise RuntimeError(f"the mesh corpus is missing at {CORPUS}; CI must not skip it")
    pytest.skip(f"SKIPPED: the mesh corpus is not at {CORPUS} (set WILDLOD_CORPUS)",
                allow_module_level=True)


def test_every_function_counts_the_triangles_an_instanced_file_draws(tmp_path):
    info = wildlod.info(TRUCK)
    drawn = info["drawn_triangles"]
    assert drawn == info["instanced"]["triangulated"]
    assert drawn > info["triangulated"]  # the wheels are drawn twice

    run = wildlod.simplify_file(TRUCK, tmp_path / "s.glb", ratio=0.25)
    assert run["input_triangles"] == drawn
    assert wildlod.info(tmp_path / "s.glb")["drawn_triangles"] == run["output_triangles"]

    chain = wildlod.lod_chain(TRUCK, tmp_path / "l.glb", ratios=[0.5, 0.25])
    assert chain["levels"][0]["triangles"] == drawn

    src = tmp_path / "in"
    src.mkdir()
    shutil.copy(TRUCK, src / "truck.glb")
    summary = wildlod.batch(src, tmp_path / "out", ratio=0.25)
    row = summary["results"][0]
    assert row["triangles_in"] == drawn
    assert wildlod.info(tmp_path / "out" / "truck.glb")["drawn_triangles"] == row["triangles_out"]

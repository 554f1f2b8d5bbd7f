"""Textures kept, re-baked or chosen per file, as the CLI does (issue 31,
decision 4): simplify_file, lod_chain and batch take textures='auto'
(the default), 'keep' or 'bake', and report the choice with the same
keys and the same measurements as `wildlod simplify --json` (the whole
file under one budget, or with per_mesh=True as `--per-mesh`)."""

import json
import os
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

import wildlod
from conftest import cli_binary

CORPUS = Path(os.environ.get("WILDLOD_CORPUS",
                             Path(__file__).resolve().parents[4] / "shared" / "corpus"))
TRUCK = CORPUS / "textured" / "CesiumMilkTruck.glb"

if not TRUCK.is_file():
    if os.environ.get("CI") == "true":
        raise RuntimeError(f"the mesh corpus is missing at {CORPUS}; CI must not skip it")
    pytest.skip(f"SKIPPED: the mesh corpus is not at {CORPUS} (set WILDLOD_CORPUS)",
                allow_module_level=True)


def baked_images(glb):
    """Names of a .glb's images that a re-bake wrote
    (`<stem>_<mesh>_<material>_<channel>`)."""
    data = Path(glb).read_bytes()
    (length,) = struct.unpack("<I", data[12:16])
    images = json.loads(data[20:20 + length]).get("images", [])
    return [i["name"] for i in images if i.get("name", "").endswith("_baseColor")]


def test_simplify_file_chooses_textures_as_the_cli_does(tmp_path):
    run = wildlod.simplify_file(TRUCK, tmp_path / "p.glb", ratio=0.1)
    cli = json.loads(subprocess.run(
        [cli_binary(), "simplify", str(TRUCK), "-o", str(tmp_path / "c.glb"), "--ratio", "0.1",
         "--json"],
        check=True, capture_output=True).stdout)
    # The truck's texture tears at 10% with its UVs kept: both re-bake,
    # with the same measurements.
    assert run["textures"] == cli["textures"]
    assert run["textures"]["mode"] == "auto"
    assert run["textures"]["chosen"] == "bake"
    assert run["output_triangles"] == cli["output_triangles"]
    assert [m["name"] for m in run["meshes"]] == [m["name"] for m in cli["meshes"]]
    per_mesh = wildlod.simplify_file(TRUCK, tmp_path / "m.glb", ratio=0.1, per_mesh=True,
                                     textures="keep")
    cli = json.loads(subprocess.run(
        [cli_binary(), "simplify", str(TRUCK), "-o", str(tmp_path / "cm.glb"), "--ratio", "0.1",
         "--per-mesh", "--textures", "keep", "--json"],
        check=True, capture_output=True).stdout)
    assert [m["output_triangles"] for m in per_mesh["meshes"]] == \
        [m["output_triangles"] for m in cli["meshes"]]

    kept = wildlod.simplify_file(TRUCK, tmp_path / "k.glb", ratio=0.1, textures="keep")
    assert kept["textures"]["chosen"] == "keep"
    assert kept["textures"]["keep_uv_excess"] is None
    # Keeping the UVs keeps the input's images; the re-bake writes its own.
    assert baked_images(tmp_path / "k.glb") == []
    assert baked_images(tmp_path / "p.glb") != []

    with pytest.raises(ValueError, match="textures"):
        wildlod.simplify_file(TRUCK, tmp_path / "x.glb", ratio=0.1, textures="rebake")
    with pytest.raises(wildlod.WildlodError, match="texture_size"):
        wildlod.simplify_file(TRUCK, tmp_path / "x.glb", ratio=0.1, textures="bake",
                              texture_size=8)


def test_lod_chain_and_batch_take_textures(tmp_path):
    chain = wildlod.lod_chain(TRUCK, tmp_path / "l.glb", ratios=[0.5, 0.1])
    chosen = [level["textures"]["chosen"] for level in chain["levels"][1:]]
    assert chosen == ["keep", "bake"], chosen

    src = tmp_path / "in"
    src.mkdir()
    shutil.copy(TRUCK, src / "truck.glb")
    for textures in ["keep", "bake"]:
        out = tmp_path / textures
        summary = wildlod.batch(src, out, ratio=0.1, textures=textures)
        assert summary["ok"] == 1, summary
        assert (baked_images(out / "truck.glb") != []) == (textures == "bake")

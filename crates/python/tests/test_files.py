"""Files: simplify_file, lod_chain, info and compare, with the keys of the
CLI's --json output, and their errors."""

import json
import os
import subprocess

import numpy as np
import pytest

import wildlod
from conftest import cli_binary, torus, write_obj


def test_simplify_file_writes_the_format_of_the_extension(torus_obj, tmp_path):
    out = tmp_path / "lod.glb"
    rep = wildlod.simplify_file(torus_obj, out, ratio=0.25)
    assert out.read_bytes()[:4] == b"glTF"
    assert rep["input"] == str(torus_obj) and rep["output"] == str(out)
    assert abs(rep["output_triangles"] - rep["input_triangles"] // 4) <= 1
    assert rep["warnings"] == []
    # What was written is what the report says.
    assert wildlod.info(out)["triangulated"] == rep["output_triangles"]


def test_simplify_file_takes_tuning_options(torus_obj, tmp_path):
    a = wildlod.simplify_file(torus_obj, tmp_path / "a.obj", ratio=0.2)
    b = wildlod.simplify_file(torus_obj, tmp_path / "b.obj", ratio=0.2, tangent_weight=1.0)
    assert (tmp_path / "a.obj").read_text() != (tmp_path / "b.obj").read_text()
    assert a["meshes"][0]["collapses"] > 0 and b["meshes"][0]["collapses"] > 0
    with pytest.raises(wildlod.WildlodError, match="symmetry must be"):
        wildlod.simplify_file(torus_obj, tmp_path / "c.obj", symmetry=-1.0)
    with pytest.raises(TypeError):
        wildlod.simplify_file(torus_obj, tmp_path / "c.obj", no_such_option=1)


def test_an_input_is_not_replaced_without_overwrite(torus_obj):
    before = torus_obj.read_bytes()
    with pytest.raises(wildlod.WildlodError, match="refusing to overwrite"):
        wildlod.simplify_file(torus_obj, torus_obj, ratio=0.5)
    assert torus_obj.read_bytes() == before
    wildlod.simplify_file(torus_obj, torus_obj, ratio=0.5, overwrite=True)
    assert torus_obj.read_bytes() != before


def test_missing_and_broken_files_raise(tmp_path):
    with pytest.raises(wildlod.WildlodOSError) as e:
        wildlod.info(tmp_path / "nope.obj")
    assert isinstance(e.value, OSError) and isinstance(e.value, wildlod.WildlodError)
    assert "nope.obj" in str(e.value)
    broken = tmp_path / "broken.ply"
    broken.write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n")
    with pytest.raises(wildlod.WildlodError) as e:
        wildlod.simplify_file(broken, tmp_path / "out.ply")
    assert not isinstance(e.value, OSError)
    assert "broken.ply" in str(e.value)
    with pytest.raises(wildlod.WildlodError, match="unsupported file extension"):
        wildlod.simplify_file(broken, tmp_path / "out.xyz")


def test_lod_chain_in_one_glb_with_msft_lod(torus_obj, tmp_path):
    out = tmp_path / "chain.glb"
    rep = wildlod.lod_chain(torus_obj, out, ratios=[0.5, 0.25, 0.1])
    assert rep["files"] == [str(out)]
    tris = [lvl["triangles"] for lvl in rep["levels"]]
    assert [lvl["level"] for lvl in rep["levels"]] == [0, 1, 2, 3]
    assert all(a > b for a, b in zip(tris, tris[1:])), tris
    cover = [lvl["screen_coverage"] for lvl in rep["levels"]]
    assert all(a >= b for a, b in zip(cover, cover[1:])), cover
    # The file holds the levels as MSFT_lod nodes with coverage hints.
    data = out.read_bytes()
    length = int.from_bytes(data[12:16], "little")
    gltf = json.loads(data[20:20 + length])
    assert "MSFT_lod" in gltf["extensionsUsed"]
    base = [n for n in gltf["nodes"] if "MSFT_lod" in n.get("extensions", {})]
    assert len(base) == 1
    assert len(base[0]["extensions"]["MSFT_lod"]["ids"]) == 3
    assert len(base[0]["extras"]["MSFT_screencoverage"]) == 4


def test_lod_chain_split_writes_one_file_per_level(torus_obj, tmp_path):
    out = tmp_path / "t.obj"
    rep = wildlod.lod_chain(torus_obj, out, errors=[0.002, 0.01])
    names = [os.path.basename(f) for f in rep["files"]]
    assert names == ["t_lod0.obj", "t_lod1.obj", "t_lod2.obj"]
    counts = [wildlod.info(f)["triangulated"] for f in rep["files"]]
    assert counts == [lvl["triangles"] for lvl in rep["levels"]]
    assert counts[0] >= counts[1] >= counts[2]
    assert rep["levels"][2]["error"] <= 0.01 + 1e-9
    faces = wildlod.lod_chain(torus_obj, tmp_path / "f.glb", faces_targets=[800, 200], split=True)
    assert len(faces["files"]) == 3
    assert abs(faces["levels"][2]["triangles"] - 200) <= 2


def test_lod_chain_refuses_lists_that_do_not_get_coarser(torus_obj, tmp_path):
    with pytest.raises(wildlod.WildlodError, match="ratios must decrease"):
        wildlod.lod_chain(torus_obj, tmp_path / "x.glb", ratios=[0.25, 0.5])
    with pytest.raises(wildlod.WildlodError, match="give one of"):
        wildlod.lod_chain(torus_obj, tmp_path / "x.glb", ratios=[0.5], errors=[0.01])
    assert not (tmp_path / "x.glb").exists()


def test_info_and_compare(torus_obj, tmp_path):
    i = wildlod.info(torus_obj)
    assert i["format"] == "obj" and i["meshes"] == 1
    assert i["triangles"] == 48 * 24 * 2 and i["components"] == 1
    assert i["boundary_edges"] == 0 and i["nonmanifold_edges"] == 0
    same = wildlod.compare(torus_obj, torus_obj, samples=5000)
    assert same["hausdorff"] < 1e-6
    lod = tmp_path / "lod.obj"
    wildlod.simplify_file(torus_obj, lod, ratio=0.05)
    far = wildlod.compare(torus_obj, lod, samples=5000)
    assert far["hausdorff"] > same["hausdorff"] and far["chamfer_mean"] > 0
    with pytest.raises(wildlod.WildlodError, match="samples must be at least 1"):
        wildlod.compare(torus_obj, lod, samples=0)


def cli_json(*args):
    out = subprocess.run([cli_binary(), *map(str, args)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_reports_have_the_keys_of_the_cli(torus_obj, tmp_path):
    """The same library runs behind both: same keys, same numbers where the
    work is deterministic."""
    py_info = wildlod.info(torus_obj)
    assert py_info == cli_json("info", torus_obj, "--json")
    py_cmp = wildlod.compare(torus_obj, torus_obj, samples=3000)
    cli_cmp = cli_json("compare", torus_obj, torus_obj, "--json", "--samples", "3000")
    assert py_cmp.keys() - {"warnings"} == cli_cmp.keys()
    assert py_cmp["hausdorff"] == cli_cmp["hausdorff"]
    py_run = wildlod.simplify_file(torus_obj, tmp_path / "a.obj", ratio=0.3)
    cli_run = cli_json("simplify", torus_obj, "-o", tmp_path / "b.obj", "--ratio", "0.3", "--json")
    assert py_run.keys() - {"warnings"} == cli_run.keys()
    assert py_run["output_triangles"] == cli_run["output_triangles"]
    assert (tmp_path / "a.obj").read_text() == (tmp_path / "b.obj").read_text()
    py_lod = wildlod.lod_chain(torus_obj, tmp_path / "a.glb", ratios=[0.5, 0.2])
    cli_lod = cli_json("lod", torus_obj, "-o", tmp_path / "b.glb", "--ratios", "0.5,0.2", "--json")
    assert py_lod.keys() - {"warnings"} == cli_lod.keys()
    assert [lv["triangles"] for lv in py_lod["levels"]] == [lv["triangles"] for lv in cli_lod["levels"]]


def test_paths_may_be_str_or_pathlike(tmp_path):
    pos, faces, _, _ = torus(16, 8)
    src = write_obj(tmp_path / "s.obj", pos, faces)
    rep = wildlod.simplify_file(str(src), os.fspath(tmp_path / "o.stl"), faces_target=64)
    assert abs(rep["output_triangles"] - 64) <= 1
    stl = (tmp_path / "o.stl").read_bytes()
    assert int.from_bytes(stl[80:84], "little") == rep["output_triangles"]
    assert np.isfinite(rep["error"])

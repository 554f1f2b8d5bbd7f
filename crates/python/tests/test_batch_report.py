"""wildlod.batch and wildlod.report: the counterparts of `wildlod batch`
and `wildlod report`, with the keys of their --json output and of
wildlod-summary.json."""

import csv
import json
import subprocess

import pytest

import wildlod
from conftest import cli_binary, torus, write_obj

SUMMARY_KEYS = {"input", "output", "files", "ok", "failed", "skipped", "seconds", "results"}
ROW_KEYS = {"file", "status", "outputs", "triangles_in", "triangles_out", "error", "seconds",
            "message"}


@pytest.fixture
def library(tmp_path):
    """Three tori in two folders, a broken file and a hidden one."""
    src = tmp_path / "assets"
    (src / "props").mkdir(parents=True)
    for name, (n, m) in {"a.obj": (24, 12), "props/b.obj": (32, 16),
                         "props/c.obj": (20, 10)}.items():
        pos, faces, _, _ = torus(n, m)
        write_obj(src / name, pos, faces)
    (src / "props" / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    (src / ".hidden.obj").write_text("v 0 0 0\n")
    return src


def test_batch_simplifies_a_tree_and_lists_the_broken_file(library, tmp_path):
    out = tmp_path / "lods"
    s = wildlod.batch(library, out, ratio=0.25, format="glb", jobs=2)
    assert set(s) == SUMMARY_KEYS
    assert (s["files"], s["ok"], s["failed"], s["skipped"]) == (4, 3, 1, 0)
    rows = {r["file"]: r for r in s["results"]}
    assert set(rows) == {"a.obj", "props/b.obj", "props/broken.obj", "props/c.obj"}
    assert all(set(r) == ROW_KEYS for r in s["results"])
    bad = rows["props/broken.obj"]
    assert bad["status"] == "failed" and "broken.obj" in bad["message"]
    assert bad["triangles_out"] is None
    for name in ["a.obj", "props/b.obj", "props/c.obj"]:
        r = rows[name]
        written = out / name.replace(".obj", ".glb")
        assert r["status"] == "ok" and r["outputs"] == [str(written)]
        assert wildlod.info(written)["triangulated"] == r["triangles_out"]
        assert abs(r["triangles_out"] - r["triangles_in"] // 4) <= 1
    # The summary files hold the same rows.
    on_disk = json.loads((out / "wildlod-summary.json").read_text())
    assert on_disk["results"] == s["results"]
    with open(out / "wildlod-summary.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [t["file"] for t in table] == [r["file"] for r in s["results"]]
    # Resumable: what exists is skipped, the broken file tried again.
    again = wildlod.batch(library, out, ratio=0.25, format="glb", skip_existing=True)
    assert (again["skipped"], again["failed"]) == (3, 1)


def test_batch_makes_chains_and_takes_tuning_options(library, tmp_path):
    out = tmp_path / "chains"
    summary = tmp_path / "only.json"
    s = wildlod.batch(library, out, lod_ratios=[0.5, 0.2], split=True, format="ply",
                      summary=summary, tangent_weight=0.5)
    assert s["ok"] == 3 and summary.exists()
    assert not (out / "wildlod-summary.json").exists()
    row = next(r for r in s["results"] if r["file"] == "a.obj")
    assert row["outputs"] == [str(out / f"a_lod{k}.ply") for k in range(3)]
    counts = [wildlod.info(f)["triangulated"] for f in row["outputs"]]
    assert counts[0] == row["triangles_in"] and counts[2] == row["triangles_out"]
    with pytest.raises(wildlod.WildlodError, match="ratios must decrease"):
        wildlod.batch(library, out, lod_ratios=[0.2, 0.5])
    with pytest.raises(TypeError):
        wildlod.batch(library, out, no_such_option=1)
    with pytest.raises(wildlod.WildlodError, match="is not a folder"):
        wildlod.batch(tmp_path / "missing", out)
    with pytest.raises(wildlod.WildlodError, match=r"\.json or \.csv"):
        wildlod.batch(library, out, summary=tmp_path / "s.txt")


def test_batch_has_the_keys_and_numbers_of_the_cli(library, tmp_path):
    py = wildlod.batch(library, tmp_path / "py", ratio=0.3, jobs=1)
    run = subprocess.run([cli_binary(), "batch", str(library), "-o", str(tmp_path / "cli"),
                          "--ratio", "0.3", "--jobs", "1", "--json"],
                         capture_output=True, text=True)
    assert run.returncode == 1, run.stderr  # the broken file fails the run
    cli = json.loads(run.stdout)
    assert py.keys() == cli.keys()
    assert [r.keys() for r in py["results"]] == [r.keys() for r in cli["results"]]
    for p, c in zip(py["results"], cli["results"]):
        assert (p["file"], p["status"], p["triangles_in"], p["triangles_out"]) == \
            (c["file"], c["status"], c["triangles_in"], c["triangles_out"])


def test_report_writes_the_page_and_returns_its_numbers(tmp_path):
    pos, faces, _, _ = torus()
    src = write_obj(tmp_path / "t.obj", pos, faces)
    lod = tmp_path / "t_lod.glb"
    wildlod.simplify_file(src, lod, ratio=0.1)
    page = tmp_path / "r.html"
    r = wildlod.report(src, lod, page, samples=5000)
    assert r["output"] == str(page) and page.read_text().startswith("<!doctype html>")
    assert r["reference_triangles"] == 48 * 24 * 2 and r["samples"] == 5000
    (c,) = r["candidates"]
    assert c["label"] == "t_lod.glb" and c["triangles"] == wildlod.info(lod)["triangulated"]
    assert c["chain_error"] is None
    same = wildlod.compare(src, lod, samples=5000)
    assert c["metrics"]["hausdorff"] == same["hausdorff"]
    assert r["warnings"] == []
    # Never over an input; a clear error for a missing one.
    with pytest.raises(wildlod.WildlodError, match="refusing to overwrite"):
        wildlod.report(src, lod, src)
    with pytest.raises(wildlod.WildlodOSError, match="missing.obj"):
        wildlod.report(tmp_path / "missing.obj", lod, page)
    with pytest.raises(wildlod.WildlodError, match="samples must be at least 1"):
        wildlod.report(src, lod, page, samples=0)


def test_report_has_the_keys_of_the_cli(tmp_path):
    pos, faces, _, _ = torus(24, 12)
    src = write_obj(tmp_path / "t.obj", pos, faces)
    lod = tmp_path / "t_lod.obj"
    wildlod.simplify_file(src, lod, ratio=0.2)
    py = wildlod.report(src, lod, tmp_path / "a.html", samples=3000)
    run = subprocess.run([cli_binary(), "report", str(src), str(lod), "-o",
                          str(tmp_path / "b.html"), "--samples", "3000", "--json"],
                         capture_output=True, text=True, check=True)
    cli = json.loads(run.stdout)
    assert py.keys() - {"warnings"} == cli.keys()
    assert py["candidates"][0].keys() == cli["candidates"][0].keys()
    assert py["candidates"][0]["metrics"] == cli["candidates"][0]["metrics"]

"""Simplify a library of assets on a Ray cluster.

Each file is one Ray task that calls :func:`wildlod.simplify_file` or
:func:`wildlod.lod_chain` on paths every node can read and write (a shared
filesystem: NFS, EFS, Lustre, a mounted bucket). Tasks get a memory hint
estimated from the file's size, so Ray does not start more large files on
a node than it holds; a task whose worker dies or that meets an ``OSError``
(a shared filesystem's hiccup) is retried up to ``max_retries`` times; a
file wildlod refuses (broken content) is not retried, it is listed as
failed and the run goes on. The result is a summary table: one dict per
file with ``file``, ``status`` ('ok', 'failed' or 'skipped'), ``outputs``,
``triangles_in``, ``triangles_out``, ``error``, ``seconds``, ``message``
(the keys of ``wildlod batch``'s summary).

    import ray, wildlod.ray
    ray.init()                      # or ray.init(address="auto") on a cluster
    rows = wildlod.ray.simplify_files(paths, "/shared/lods", ratio=0.25)
    failed = [r for r in rows if r["status"] == "failed"]

On a real cluster (README "Ray"): start the head with ``ray start --head``
and every worker with ``ray start --address=HEAD:6379``, install this
package on every node (the same version), mount the shared storage at the
same path everywhere, and call ``ray.init(address="auto")`` from the
driver. Ray needs ``ray`` from PyPI (``pip install 'wildlod[ray]'``).
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

import wildlod
from ._errors import WildlodError

PathLike = Union[str, "os.PathLike[str]"]

#: Memory a task is granted besides the estimate from its file's size.
BASE_MEMORY = 256 * 1024 * 1024
#: Bytes of working memory per byte of input file. A binary mesh file holds
#: about 20 to 50 bytes per triangle and the simplifier works with a few
#: hundred bytes per triangle (the complex, quadrics, heap, attributes,
#: and the output being written), so 32 covers binary files with room;
#: text formats (OBJ, ASCII PLY) are larger per triangle and need less.
MEMORY_PER_FILE_BYTE = 32


def memory_hint(path: PathLike, per_byte: float = MEMORY_PER_FILE_BYTE,
                base: int = BASE_MEMORY) -> int:
    """The memory (bytes) to reserve for one task on ``path``: ``base`` plus
    ``per_byte`` times the file's size (``base`` alone when it cannot be
    read: the task will then say why)."""
    try:
        size = os.path.getsize(path)
    except OSError:
        size = 0
    return int(base + per_byte * size)


def _row(file: str, outputs: List[str]) -> Dict[str, Any]:
    return {
        "file": file,
        "status": "failed",
        "outputs": outputs,
        "triangles_in": None,
        "triangles_out": None,
        "error": None,
        "seconds": 0.0,
        "message": "",
    }


def _outputs_for(kind: str, dst: Path, kwargs: Dict[str, Any]) -> List[str]:
    """The files a task writes (to skip existing ones and to report)."""
    if kind == "simplify":
        return [str(dst)]
    levels = kwargs.get("ratios") or kwargs.get("errors") or kwargs.get("faces_targets")
    n = len(levels) if levels else 3
    if dst.suffix.lower() in (".gltf", ".glb") and not kwargs.get("split", False):
        return [str(dst)]
    return [str(dst.with_name(f"{dst.stem}_lod{k}{dst.suffix}")) for k in range(n + 1)]


def _work(kind: str, src: str, dst: str, kwargs: Dict[str, Any]) -> Dict[str, Any]:
    """One file; runs on a Ray worker. ``OSError`` propagates (Ray retries
    it); a refused file becomes a failed row (retrying cannot help)."""
    t0 = time.perf_counter()
    row = _row(src, [])
    Path(dst).parent.mkdir(parents=True, exist_ok=True)
    try:
        if kind == "simplify":
            r = wildlod.simplify_file(src, dst, **kwargs)
            row.update(outputs=[r["output"]], triangles_in=r["input_triangles"],
                       triangles_out=r["output_triangles"], error=r["error"])
        else:
            r = wildlod.lod_chain(src, dst, **kwargs)
            last = r["levels"][-1]
            row.update(outputs=r["files"], triangles_in=r["levels"][0]["triangles"],
                       triangles_out=last["triangles"], error=last["error"])
        row["status"] = "ok"
        row["message"] = "; ".join(r.get("warnings", []))
    except OSError:
        raise
    except WildlodError as e:
        row["message"] = str(e)
    row["seconds"] = time.perf_counter() - t0
    return row


def map_files(
    func: Callable[[str, str], Dict[str, Any]],
    paths: Iterable[PathLike],
    out_dir: PathLike,
    *,
    root: Optional[PathLike] = None,
    suffix: Optional[str] = None,
    max_retries: int = 2,
    memory: Optional[Callable[[str], int]] = None,
    num_cpus: float = 1,
    outputs: Optional[Callable[[Path], List[str]]] = None,
    skip_existing: bool = False,
) -> List[Dict[str, Any]]:
    """Runs ``func(src, dst)`` on every path as a Ray task and returns the
    summary table, in the order of ``paths``.

    ``dst`` mirrors ``src`` below ``out_dir``: its path relative to ``root``
    (default: the inputs' common folder), with ``suffix`` (e.g. ".glb") when
    given. ``func`` returns a row (see the module) or raises: ``OSError``
    is retried up to ``max_retries`` times, like a worker that died; what
    still fails becomes a failed row. ``memory(src)`` gives each task's
    memory hint in bytes (default :func:`memory_hint`); ``num_cpus`` its
    CPUs. ``skip_existing`` skips files whose ``outputs(dst)`` all exist.
    Needs ``ray.init()`` first (or starts a local Ray).
    """
    import ray

    srcs = [os.fspath(p) for p in paths]
    if not srcs:
        return []
    base = Path(root) if root is not None else Path(os.path.commonpath(
        [os.path.dirname(os.path.abspath(p)) for p in srcs]))
    memory = memory or memory_hint
    outputs = outputs or (lambda d: [str(d)])
    remote = ray.remote(func)
    rows: List[Optional[Dict[str, Any]]] = [None] * len(srcs)
    pending = {}
    for i, src in enumerate(srcs):
        rel = os.path.relpath(os.path.abspath(src), os.path.abspath(base))
        if rel.startswith(".."):
            rel = os.path.basename(src)
        dst = Path(out_dir) / rel
        if suffix:
            dst = dst.with_suffix(suffix)
        if skip_existing and all(os.path.exists(o) for o in outputs(dst)):
            row = _row(src, outputs(dst))
            row.update(status="skipped", message="outputs exist")
            rows[i] = row
            continue
        # The storage is shared: the driver makes the folders once.
        dst.parent.mkdir(parents=True, exist_ok=True)
        ref = remote.options(
            memory=memory(src),
            num_cpus=num_cpus,
            max_retries=max_retries,
            # Retry what a retry can fix: the file system, not the content.
            retry_exceptions=[OSError],
        ).remote(src, str(dst))
        pending[ref] = (i, src, dst, time.perf_counter())
    while pending:
        done, _ = ray.wait(list(pending), num_returns=1)
        for ref in done:
            i, src, dst, t0 = pending.pop(ref)
            try:
                rows[i] = ray.get(ref)
            except Exception as e:  # noqa: BLE001 - every failure becomes a row
                row = _row(src, [])
                cause = getattr(e, "cause", None) or e
                row["message"] = f"{type(cause).__name__}: {cause}"
                row["seconds"] = time.perf_counter() - t0
                rows[i] = row
    return [r for r in rows if r is not None]


def simplify_files(
    paths: Iterable[PathLike],
    out_dir: PathLike,
    *,
    root: Optional[PathLike] = None,
    format: Optional[str] = None,
    max_retries: int = 2,
    memory: Optional[Callable[[str], int]] = None,
    skip_existing: bool = False,
    **kwargs: Any,
) -> List[Dict[str, Any]]:
    """:func:`wildlod.simplify_file` on every path as a Ray task (see
    :func:`map_files`); ``kwargs`` go to it (``ratio``, ``faces_target``,
    ``error``, tuning options); ``format`` ('glb', 'obj'…) changes the
    outputs' format."""
    suffix = "." + format.lstrip(".") if format else None

    def task(src: str, dst: str) -> Dict[str, Any]:
        return _work("simplify", src, dst, kwargs)

    return map_files(task, paths, out_dir, root=root, suffix=suffix,
                     max_retries=max_retries, memory=memory, skip_existing=skip_existing,
                     outputs=lambda d: _outputs_for("simplify", d, kwargs))


def lod_chains(
    paths: Iterable[PathLike],
    out_dir: PathLike,
    *,
    root: Optional[PathLike] = None,
    format: Optional[str] = None,
    max_retries: int = 2,
    memory: Optional[Callable[[str], int]] = None,
    skip_existing: bool = False,
    **kwargs: Any,
) -> List[Dict[str, Any]]:
    """:func:`wildlod.lod_chain` on every path as a Ray task (see
    :func:`map_files`); ``kwargs`` go to it (``ratios``, ``errors``,
    ``faces_targets``, ``split``, tuning options). A chain keeps every
    level in memory, so its memory hint is twice a single file's."""
    suffix = "." + format.lstrip(".") if format else None

    def task(src: str, dst: str) -> Dict[str, Any]:
        return _work("lod", src, dst, kwargs)

    return map_files(task, paths, out_dir, root=root, suffix=suffix,
                     max_retries=max_retries,
                     memory=memory or (lambda p: memory_hint(p, per_byte=2 * MEMORY_PER_FILE_BYTE)),
                     skip_existing=skip_existing,
                     outputs=lambda d: _outputs_for("lod", d, kwargs))


def summary_text(rows: Sequence[Dict[str, Any]]) -> str:
    """The table as aligned text, one line per file, and a count line."""
    lines = []
    for r in rows:
        tri = (f"{r['triangles_in']} -> {r['triangles_out']}"
               if r["triangles_in"] is not None else "-")
        err = f"{r['error']:.4f}" if r["error"] is not None else "-"
        lines.append(f"{r['status']:8} {tri:>20} {err:>8} {r['seconds']:7.2f}s  {r['file']}"
                     + (f"  ({r['message']})" if r["message"] and r["status"] != "ok" else ""))
    count = {s: sum(r["status"] == s for r in rows) for s in ("ok", "failed", "skipped")}
    lines.append(f"{len(rows)} files: {count['ok']} ok, {count['failed']} failed, "
                 f"{count['skipped']} skipped")
    return "\n".join(lines)

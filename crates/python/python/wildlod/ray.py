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

Paths and ``out_dir`` may also be object-store URLs (``s3://``, ``gs://``,
``az://``, any URL `fsspec <https://filesystem-spec.readthedocs.io>`_
opens, with its package: ``s3fs``, ``gcsfs``…), so no shared filesystem
is needed. Each task then downloads its file (and the files a ``.gltf``
or ``.obj`` refers to beside it: buffers, images, MTL and textures) into
a temporary folder on its node, simplifies it there, uploads every file
written (with their images and sidecars) below ``out_dir``, and removes
the folder, whether the task succeeded or not. ``storage_options`` go to
fsspec (credentials, ``{"client_kwargs": {"endpoint_url": ...}}`` for an
S3-compatible server). A download or upload that fails is an ``OSError``,
retried like a shared filesystem's.

    rows = wildlod.ray.simplify_files(["s3://assets/chair.glb"], "s3://lods",
                                      ratio=0.25)
"""

from __future__ import annotations

import contextlib
import json
import os
import posixpath
import re
import tempfile
import time
from pathlib import Path
from urllib.parse import unquote
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

import wildlod
from ._errors import WildlodError

PathLike = Union[str, "os.PathLike[str]"]

#: Prefix of the temporary folders tasks on object-store paths work in.
TEMP_PREFIX = "wildlod-ray-"
#: MTL statements naming a texture besides ``map_*`` (its last argument).
MTL_MAPS = ("bump", "disp", "decal", "norm", "refl")


#: Memory a task is granted besides the estimate from its file's size.
BASE_MEMORY = 256 * 1024 * 1024
#: Bytes of working memory per byte of input file. A binary mesh file holds
#: about 20 to 50 bytes per triangle and the simplifier works with a few
#: hundred bytes per triangle (the complex, quadrics, heap, attributes,
#: and the output being written), so 32 covers binary files with room;
#: text formats (OBJ, ASCII PLY) are larger per triangle and need less.
MEMORY_PER_FILE_BYTE = 32


def is_url(path: PathLike) -> bool:
    """Whether ``path`` is a URL for fsspec (``s3://bucket/key``…) rather
    than a local path."""
    return re.match(r"^[A-Za-z][A-Za-z0-9+.-]*://", os.fspath(path)) is not None


def _fs(url: str, storage_options: Optional[Dict[str, Any]]):
    """The fsspec filesystem of ``url`` and the path within it."""
    try:
        import fsspec
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise WildlodError(f"{url}: object-store paths need fsspec (pip install fsspec s3fs)") from e
    return fsspec.core.url_to_fs(url, **(storage_options or {}))


def _url_join(base: str, rel: str) -> str:
    return base.rstrip("/") + "/" + rel.replace(os.sep, "/").lstrip("/")


def _url_parent(url: str) -> str:
    return url.rsplit("/", 1)[0] if "/" in url.split("://", 1)[1] else url


def _with_suffix(path: str, suffix: str) -> str:
    root, _ = posixpath.splitext(path) if is_url(path) else os.path.splitext(path)
    return root + suffix


def memory_hint(path: PathLike, per_byte: float = MEMORY_PER_FILE_BYTE,
                base: int = BASE_MEMORY,
                storage_options: Optional[Dict[str, Any]] = None) -> int:
    """The memory (bytes) to reserve for one task on ``path`` (a local path
    or an fsspec URL): ``base`` plus ``per_byte`` times the file's size
    (``base`` alone when it cannot be read: the task will then say why)."""
    try:
        if is_url(path):
            fs, p = _fs(os.fspath(path), storage_options)
            size = int(fs.size(p) or 0)
        else:
            size = os.path.getsize(path)
    except Exception:  # noqa: BLE001 - any failure: the task reports it
        size = 0
    return int(base + per_byte * size)


def _exists(path: str, storage_options: Optional[Dict[str, Any]]) -> bool:
    if not is_url(path):
        return os.path.exists(path)
    try:
        fs, p = _fs(path, storage_options)
        return bool(fs.exists(p))
    except Exception:  # noqa: BLE001 - an unreadable output is redone
        return False


def _referenced(local: str) -> List[str]:
    """Relative paths a downloaded ``.gltf`` or ``.obj`` (and its MTL files)
    refers to, to fetch beside it; data URIs and absolute paths are not
    fetched (the reader says what is missing)."""
    out: List[str] = []
    ext = os.path.splitext(local)[1].lower()
    try:
        if ext == ".gltf":
            with open(local, encoding="utf-8") as f:
                doc = json.load(f)
            for key in ("buffers", "images"):
                for item in doc.get(key, []) or []:
                    uri = item.get("uri") if isinstance(item, dict) else None
                    if isinstance(uri, str) and not uri.startswith("data:") and not is_url(uri):
                        out.append(unquote(uri))
        elif ext == ".obj":
            with open(local, encoding="utf-8", errors="replace") as f:
                for line in f:
                    parts = line.split()
                    if parts[:1] == ["mtllib"]:
                        out.extend(parts[1:])
        elif ext == ".mtl":
            with open(local, encoding="utf-8", errors="replace") as f:
                for line in f:
                    parts = line.split()
                    if parts and (parts[0].startswith("map_") or parts[0] in MTL_MAPS):
                        out.append(parts[-1])
    except (OSError, ValueError):
        return out
    return [r for r in out if r and not os.path.isabs(r) and ".." not in Path(r).parts]


@contextlib.contextmanager
def _naming(url: str):
    """Re-raises an ``OSError`` (the same class, so Ray still retries it)
    with ``url`` in front: object stores' messages rarely name the key."""
    try:
        yield
    except OSError as e:
        try:
            named = type(e)(f"{url}: {e}")
        except Exception:  # noqa: BLE001 - a class with another signature
            named = OSError(f"{url}: {e}")
        raise named from e


def _download(url: str, folder: str, storage_options: Optional[Dict[str, Any]]) -> str:
    """Downloads ``url`` and what it refers to beside it into ``folder``;
    returns the local path of ``url``. A missing sidecar is left to the
    reader to report."""
    fs, remote = _fs(url, storage_options)
    local = os.path.join(folder, posixpath.basename(remote))
    with _naming(url):
        fs.get_file(remote, local)
    # (local file, the remote folder its relative references start from)
    todo = [(local, posixpath.dirname(remote))]
    seen = {local}
    while todo:
        path, remote_dir = todo.pop()
        for rel in _referenced(path):
            target = os.path.normpath(os.path.join(os.path.dirname(path), *rel.split("/")))
            if target in seen:
                continue
            seen.add(target)
            source = posixpath.join(remote_dir, rel)
            os.makedirs(os.path.dirname(target), exist_ok=True)
            try:
                fs.get_file(source, target)
            except FileNotFoundError:
                continue
            todo.append((target, posixpath.dirname(source)))
    return local


def _upload(folder: str, url_dir: str, storage_options: Optional[Dict[str, Any]]) -> None:
    """Uploads every file below ``folder`` to the same relative path below
    ``url_dir``."""
    fs, remote = _fs(url_dir, storage_options)
    for dirpath, _, names in os.walk(folder):
        for name in sorted(names):
            local = os.path.join(dirpath, name)
            rel = os.path.relpath(local, folder).replace(os.sep, "/")
            with _naming(_url_join(url_dir, rel)):
                fs.put_file(local, posixpath.join(remote, rel))


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


def _outputs_for(kind: str, dst: str, kwargs: Dict[str, Any]) -> List[str]:
    """The files a task writes (to skip existing ones and to report)."""
    if kind == "simplify":
        return [dst]
    levels = kwargs.get("ratios") or kwargs.get("errors") or kwargs.get("faces_targets")
    n = len(levels) if levels else 3
    root, ext = (posixpath if is_url(dst) else os.path).splitext(dst)
    if ext.lower() in (".gltf", ".glb") and not kwargs.get("split", False):
        return [dst]
    return [f"{root}_lod{k}{ext}" for k in range(n + 1)]


def _run(kind: str, src: str, dst: str, kwargs: Dict[str, Any], row: Dict[str, Any]) -> List[str]:
    """Runs wildlod on local paths, fills ``row``; returns the files written."""
    if kind == "simplify":
        r = wildlod.simplify_file(src, dst, **kwargs)
        row.update(triangles_in=r["input_triangles"], triangles_out=r["output_triangles"],
                   error=r["error"])
        files = [r["output"]]
    else:
        r = wildlod.lod_chain(src, dst, **kwargs)
        last = r["levels"][-1]
        row.update(triangles_in=r["levels"][0]["triangles"], triangles_out=last["triangles"],
                   error=last["error"])
        files = r["files"]
    row["status"] = "ok"
    row["message"] = "; ".join(r.get("warnings", []))
    return files


def _remote_names(message: str, names: Dict[str, str]) -> str:
    """``message`` with the task's temporary folders named by the URLs
    they stand for: the local paths mean nothing to the caller."""
    for local, remote in names.items():
        message = message.replace(local, remote)
    return message


def _work(kind: str, src: str, dst: str, kwargs: Dict[str, Any],
          storage_options: Optional[Dict[str, Any]] = None) -> Dict[str, Any]:
    """One file; runs on a Ray worker. ``OSError`` propagates (Ray retries
    it); a refused file becomes a failed row (retrying cannot help).
    Object-store paths are fetched into a temporary folder and the outputs
    sent back from it; the folder goes either way."""
    t0 = time.perf_counter()
    row = _row(src, [])
    try:
        if not (is_url(src) or is_url(dst)):
            Path(dst).parent.mkdir(parents=True, exist_ok=True)
            row["outputs"] = _run(kind, src, dst, kwargs, row)
        else:
            with tempfile.TemporaryDirectory(prefix=TEMP_PREFIX) as tmp:
                inbox = os.path.join(tmp, "in")
                outbox = os.path.join(tmp, "out")
                os.makedirs(inbox)
                os.makedirs(outbox)
                names = {}
                local_src = src
                if is_url(src):
                    local_src = _download(src, inbox, storage_options)
                    names[inbox + os.sep] = _url_parent(src) + "/"
                if is_url(dst):
                    local_dst = os.path.join(outbox, posixpath.basename(dst))
                    names[outbox + os.sep] = _url_parent(dst) + "/"
                else:
                    Path(dst).parent.mkdir(parents=True, exist_ok=True)
                    local_dst = dst
                try:
                    written = _run(kind, local_src, local_dst, kwargs, row)
                except WildlodError as e:
                    # The same class (an OSError stays one, to be retried).
                    raise type(e)(_remote_names(str(e), names)) from None
                if is_url(dst):
                    remote_dir = _url_parent(dst)
                    _upload(outbox, remote_dir, storage_options)
                    written = [_url_join(remote_dir, os.path.relpath(f, outbox)) for f in written]
                row["outputs"] = written
                row["message"] = _remote_names(row["message"], names)
    except OSError:
        raise
    except WildlodError as e:
        row["status"] = "failed"
        row["message"] = str(e)
    row["seconds"] = time.perf_counter() - t0
    return row


def _common_folder(srcs: List[str]) -> str:
    """The deepest folder (or URL prefix) holding every path."""
    if all(is_url(p) for p in srcs):
        scheme = {p.split("://", 1)[0] for p in srcs}
        if len(scheme) == 1:
            rests = [posixpath.dirname(p.split("://", 1)[1]) for p in srcs]
            return scheme.pop() + "://" + posixpath.commonpath(rests)
        return ""
    if any(is_url(p) for p in srcs):
        return ""
    return os.path.commonpath([os.path.dirname(os.path.abspath(p)) for p in srcs])


def _destination(src: str, base: str, out: str) -> str:
    """``src``'s path relative to ``base`` below ``out`` (its name alone
    when it is not below ``base``)."""
    if is_url(src):
        prefix = base.rstrip("/") + "/"
        rel = src[len(prefix):] if base and src.startswith(prefix) else posixpath.basename(src)
    else:
        rel = os.path.relpath(os.path.abspath(src), os.path.abspath(base)) if base and not is_url(base) else ".."
        if rel.startswith(".."):
            rel = os.path.basename(src)
    if is_url(out):
        return _url_join(out, rel)
    return str(Path(out) / rel)


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
    outputs: Optional[Callable[[str], List[str]]] = None,
    skip_existing: bool = False,
    storage_options: Optional[Dict[str, Any]] = None,
) -> List[Dict[str, Any]]:
    """Runs ``func(src, dst)`` on every path as a Ray task and returns the
    summary table, in the order of ``paths``.

    ``dst`` mirrors ``src`` below ``out_dir``: its path relative to ``root``
    (default: the inputs' common folder), with ``suffix`` (e.g. ".glb") when
    given. Paths and ``out_dir`` may be fsspec URLs (``s3://…``); ``dst``
    is then a URL too. ``func`` returns a row (see the module) or raises:
    ``OSError`` is retried up to ``max_retries`` times, like a worker that
    died; what still fails becomes a failed row. ``memory(src)`` gives each
    task's memory hint in bytes (default :func:`memory_hint`); ``num_cpus``
    its CPUs. ``skip_existing`` skips files whose ``outputs(dst)`` all
    exist (``storage_options`` open the URLs). Needs ``ray.init()`` first
    (or starts a local Ray).
    """
    import ray

    srcs = [os.fspath(p) for p in paths]
    if not srcs:
        return []
    out = os.fspath(out_dir)
    base = os.fspath(root) if root is not None else _common_folder(srcs)
    memory = memory or (lambda p: memory_hint(p, storage_options=storage_options))
    outputs = outputs or (lambda d: [d])
    remote = ray.remote(func)
    rows: List[Optional[Dict[str, Any]]] = [None] * len(srcs)
    pending = {}
    for i, src in enumerate(srcs):
        dst = _destination(src, base, out)
        if suffix:
            dst = _with_suffix(dst, suffix)
        if skip_existing and all(_exists(o, storage_options) for o in outputs(dst)):
            row = _row(src, outputs(dst))
            row.update(status="skipped", message="outputs exist")
            rows[i] = row
            continue
        if not is_url(dst):
            # The storage is shared: the driver makes the folders once.
            Path(dst).parent.mkdir(parents=True, exist_ok=True)
        ref = remote.options(
            memory=memory(src),
            num_cpus=num_cpus,
            max_retries=max_retries,
            # Retry what a retry can fix: the file system, not the content.
            retry_exceptions=[OSError],
        ).remote(src, dst)
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
    storage_options: Optional[Dict[str, Any]] = None,
    **kwargs: Any,
) -> List[Dict[str, Any]]:
    """:func:`wildlod.simplify_file` on every path as a Ray task (see
    :func:`map_files`); ``kwargs`` go to it (``ratio``, ``faces_target``,
    ``error``, tuning options); ``format`` ('glb', 'obj'…) changes the
    outputs' format. Paths and ``out_dir`` may be fsspec URLs, opened with
    ``storage_options`` (see the module)."""
    suffix = "." + format.lstrip(".") if format else None

    def task(src: str, dst: str) -> Dict[str, Any]:
        return _work("simplify", src, dst, kwargs, storage_options)

    return map_files(task, paths, out_dir, root=root, suffix=suffix,
                     max_retries=max_retries, memory=memory, skip_existing=skip_existing,
                     outputs=lambda d: _outputs_for("simplify", d, kwargs),
                     storage_options=storage_options)


def lod_chains(
    paths: Iterable[PathLike],
    out_dir: PathLike,
    *,
    root: Optional[PathLike] = None,
    format: Optional[str] = None,
    max_retries: int = 2,
    memory: Optional[Callable[[str], int]] = None,
    skip_existing: bool = False,
    storage_options: Optional[Dict[str, Any]] = None,
    **kwargs: Any,
) -> List[Dict[str, Any]]:
    """:func:`wildlod.lod_chain` on every path as a Ray task (see
    :func:`map_files`); ``kwargs`` go to it (``ratios``, ``errors``,
    ``faces_targets``, ``split``, tuning options). A chain keeps every
    level in memory, so its memory hint is twice a single file's. Paths
    and ``out_dir`` may be fsspec URLs, opened with ``storage_options``."""
    suffix = "." + format.lstrip(".") if format else None

    def task(src: str, dst: str) -> Dict[str, Any]:
        return _work("lod", src, dst, kwargs, storage_options)

    def hint(p: str) -> int:
        return memory_hint(p, per_byte=2 * MEMORY_PER_FILE_BYTE, storage_options=storage_options)

    return map_files(task, paths, out_dir, root=root, suffix=suffix,
                     max_retries=max_retries, memory=memory or hint,
                     skip_existing=skip_existing,
                     outputs=lambda d: _outputs_for("lod", d, kwargs),
                     storage_options=storage_options)


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

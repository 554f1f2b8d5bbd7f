"""wildlod.ray on object-store paths: a local S3-compatible server (moto in
server mode, on loopback, started and stopped here), files read from one
bucket and written to another by Ray tasks, a broken file among them, and
no temporary folder left behind. moto, boto3, s3fs and ray are installed
by .ci/run; without them the tests are skipped loudly, and fail under
CI=true."""

import glob
import os
import tempfile

import pytest

import wildlod
from conftest import IN_CI, torus, write_obj

try:
    import boto3
    import ray
    import s3fs  # noqa: F401 - fsspec's s3:// needs it in the tasks
    from moto.server import ThreadedMotoServer
except ImportError as e:  # pragma: no cover - depends on the environment
    if IN_CI:
        raise
    pytest.skip(f"SKIPPED: {e.name} is not installed (pip install ray fsspec s3fs "
                "'moto[server]' boto3)", allow_module_level=True)

import wildlod.ray as wray

# moto accepts any credentials; these keep boto from looking for real ones.
CREDENTIALS = {"AWS_ACCESS_KEY_ID": "testing", "AWS_SECRET_ACCESS_KEY": "testing",
               "AWS_DEFAULT_REGION": "us-east-1"}


@pytest.fixture(scope="module")
def s3():
    """The server on an ephemeral loopback port, and the storage options
    that reach it."""
    old = {k: os.environ.get(k) for k in CREDENTIALS}
    os.environ.update(CREDENTIALS)
    server = ThreadedMotoServer(ip_address="127.0.0.1", port=0, verbose=False)
    server.start()
    host, port = server.get_host_and_port()
    endpoint = f"http://{host}:{port}"
    client = boto3.client("s3", endpoint_url=endpoint, region_name="us-east-1")
    for bucket in ("assets", "lods"):
        client.create_bucket(Bucket=bucket)
    options = {"key": "testing", "secret": "testing",
               "client_kwargs": {"endpoint_url": endpoint, "region_name": "us-east-1"}}
    yield client, options
    server.stop()
    for k, v in old.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, object_store_memory=128 * 1024 * 1024,
             log_to_driver=False, configure_logging=False)
    yield
    ray.shutdown()


@pytest.fixture
def uploaded(s3, tmp_path):
    """Three tori (one a .gltf with its .bin beside it) and a broken OBJ in
    s3://assets/lib/…"""
    client, _ = s3
    local = tmp_path / "src"
    local.mkdir()
    keys = []
    for k, (n, m) in enumerate([(24, 12), (32, 16), (20, 10)]):
        pos, faces, _, _ = torus(n, m)
        path = write_obj(local / f"mesh{k}.obj", pos, faces)
        folder = "props" if k % 2 else "chars"
        if k == 2:
            # A .gltf refers to its .bin: both must reach the task.
            wildlod.simplify_file(path, local / "mesh2.gltf", ratio=1.0)
            client.upload_file(str(local / "mesh2.bin"), "assets", f"lib/{folder}/mesh2.bin")
            path = local / "mesh2.gltf"
        key = f"lib/{folder}/{path.name}"
        client.upload_file(str(path), "assets", key)
        keys.append(key)
    (local / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    client.upload_file(str(local / "broken.obj"), "assets", "lib/props/broken.obj")
    keys.insert(1, "lib/props/broken.obj")
    return [f"s3://assets/{k}" for k in keys]


def leftovers():
    return set(glob.glob(os.path.join(tempfile.gettempdir(), wray.TEMP_PREFIX + "*")))


def fetch(client, url, folder):
    """Downloads an output (and nothing else) to check it."""
    bucket, key = url[len("s3://"):].split("/", 1)
    local = os.path.join(folder, key.replace("/", "_"))
    client.download_file(bucket, key, local)
    return local


def test_files_are_read_from_and_written_to_buckets(s3, local_ray, uploaded, tmp_path):
    client, options = s3
    before = leftovers()
    rows = wray.simplify_files(uploaded, "s3://lods/out", ratio=0.25, format="glb",
                               storage_options=options, max_retries=1)
    assert [r["file"] for r in rows] == uploaded
    bad = [r for r in rows if r["status"] == "failed"]
    assert [r["file"] for r in bad] == ["s3://assets/lib/props/broken.obj"]
    # The message names the object, not the task's temporary copy.
    assert "s3://assets/lib/props/broken.obj" in bad[0]["message"], bad[0]["message"]
    assert bad[0]["outputs"] == []
    for r in rows:
        if r in bad:
            continue
        assert r["status"] == "ok", r
        rel = r["file"][len("s3://assets/lib/"):]
        assert r["outputs"] == ["s3://lods/out/" + rel.rsplit(".", 1)[0] + ".glb"]
        local = fetch(client, r["outputs"][0], tmp_path)
        assert wildlod.info(local)["triangulated"] == r["triangles_out"]
        assert abs(r["triangles_out"] - r["triangles_in"] // 4) <= 1
    # Nothing else was written, and every temporary folder is gone.
    listed = client.list_objects_v2(Bucket="lods", Prefix="out/")
    assert sorted(o["Key"] for o in listed["Contents"]) == sorted(
        r["outputs"][0][len("s3://lods/"):] for r in rows if r not in bad)
    assert leftovers() <= before
    # Resumable on the bucket too.
    again = wray.simplify_files(uploaded, "s3://lods/out", ratio=0.25, format="glb",
                                storage_options=options, skip_existing=True)
    assert [r["status"] for r in again].count("skipped") == 3


def test_chains_go_to_a_bucket_with_every_level_and_sidecar(s3, local_ray, uploaded):
    client, options = s3
    good = [u for u in uploaded if not u.endswith("broken.obj")]
    rows = wray.lod_chains(good, "s3://lods/chains", ratios=[0.5, 0.2], split=True,
                           format="gltf", storage_options=options)
    assert all(r["status"] == "ok" for r in rows), rows
    keys = {o["Key"] for o in client.list_objects_v2(Bucket="lods", Prefix="chains/")["Contents"]}
    for r in rows:
        assert len(r["outputs"]) == 3
        for url in r["outputs"]:
            key = url[len("s3://lods/"):]
            # Each .gltf with the .bin it refers to.
            assert key in keys and key[:-len(".gltf")] + ".bin" in keys, (key, keys)


def test_a_missing_object_is_retried_then_listed(s3, local_ray):
    _, options = s3
    rows = wray.simplify_files(["s3://assets/lib/nope.obj"], "s3://lods/x", ratio=0.5,
                               storage_options=options, max_retries=1)
    assert rows[0]["status"] == "failed"
    assert "nope.obj" in rows[0]["message"] and "FileNotFoundError" in rows[0]["message"]

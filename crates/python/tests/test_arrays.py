"""wildlod.simplify on numpy arrays: triangles, polygons, streams, options,
errors, and the GIL released while it works."""

import threading
import time

import numpy as np
import pytest

import wildlod
from conftest import grid, torus

REPORT_KEYS = {"name", "mesh", "input_triangles", "target_triangles", "output_triangles",
               "error", "stop", "collapses", "split_polygons", "hidden_twins", "enclosed_parts", "twin_slack",
               "seconds",
               "outliers", "steering", "uv_damage", "evaluations", "faces_tested", "rejected",
               "virtual_radius_reduced", "layer_vertices", "held_by_constraints", "quad_ties"}


def check_faces(out, sizes=None):
    n = len(out["positions"])
    assert out["indices"].dtype == np.uint32
    assert out["indices"].max() < n, "an index points past the vertices"
    assert out["face_sizes"].sum() == len(out["indices"])
    if sizes is not None:
        assert set(np.unique(out["face_sizes"])) <= set(sizes)


def test_triangles_in_triangles_out_at_the_ratio():
    pos, faces, _, _ = torus()
    out = wildlod.simplify(pos, faces, ratio=0.25)
    rep = out["report"]
    assert set(rep) == REPORT_KEYS
    assert rep["input_triangles"] == len(faces)
    assert abs(rep["output_triangles"] - len(faces) // 4) <= 1
    assert out["faces"].shape == (rep["output_triangles"], 3)
    assert out["positions"].shape[1] == 3 and out["positions"].dtype == np.float32
    check_faces(out, {3})
    # The torus stays a torus: every output vertex lies near its surface.
    p = out["positions"].astype(np.float64)
    ring = np.hypot(p[:, 0], p[:, 1]) - 1.0
    dist = np.abs(np.hypot(ring, p[:, 2]) - 0.35)
    assert dist.max() < 0.05, dist.max()


def test_faces_target_and_error_limit():
    pos, faces, _, _ = torus()
    out = wildlod.simplify(pos, faces, faces_target=300)
    assert abs(out["report"]["output_triangles"] - 300) <= 1
    loose = wildlod.simplify(pos, faces, ratio=0.0, error=0.02)
    tight = wildlod.simplify(pos, faces, ratio=0.0, error=0.002)
    assert loose["report"]["error"] <= 0.02
    assert tight["report"]["error"] <= 0.002
    assert tight["report"]["stop"] == "error_limit"
    assert loose["report"]["output_triangles"] < tight["report"]["output_triangles"]


def test_uvs_normals_and_colors_come_back_per_vertex():
    pos, faces, uvs, normals = torus()
    colors = np.column_stack([uvs, np.full(len(uvs), 0.5)])
    out = wildlod.simplify(pos, faces, ratio=0.3, uvs=uvs, normals=normals, colors=colors)
    n = len(out["positions"])
    assert out["uvs"].shape == (n, 2)
    assert out["normals"].shape == (n, 3)
    assert out["colors"].shape == (n, 3)
    check_faces(out, {3})
    # Fitted values stay within the input's range; normals are unit.
    assert out["uvs"].min() >= -1e-3 and out["uvs"].max() <= 1 + 1e-3
    assert np.allclose(np.linalg.norm(out["normals"], axis=1), 1.0, atol=1e-3)
    assert np.allclose(out["colors"][:, 2], 0.5, atol=1e-3)
    # A normal still points away from the tube's core.
    p = out["positions"].astype(np.float64)
    core = p.copy()
    core[:, 2] = 0
    core[:, :2] *= (1.0 / np.maximum(np.hypot(p[:, 0], p[:, 1]), 1e-9))[:, None]
    outward = np.einsum("ij,ij->i", out["normals"], p - core)
    assert (outward > 0).mean() > 0.99


def test_a_uv_seam_splits_vertices_on_the_way_out():
    # Two triangles sharing an edge whose corners have different UVs per
    # side: given per vertex, a seam needs duplicated positions.
    pos, faces, uvs, _ = torus()
    out = wildlod.simplify(pos, faces, ratio=0.5, uvs=uvs)
    # The torus's UVs wrap: u = 0 and u = 1 meet at welded positions whose
    # vertices carry u from both sides only if split; no NaN either way.
    assert np.isfinite(out["uvs"]).all()
    assert len(out["positions"]) >= len(np.unique(out["indices"]))


def test_skin_weights_come_back_normalized():
    pos, faces, _, _ = torus()
    k = 2
    joints = np.column_stack([np.zeros(len(pos), int), np.ones(len(pos), int)])
    w0 = (pos[:, 0] - pos[:, 0].min()) / np.ptp(pos[:, 0])
    weights = np.column_stack([w0, 1 - w0])
    out = wildlod.simplify(pos, faces, ratio=0.3, joints=joints, weights=weights)
    n = len(out["positions"])
    assert out["joints"].shape == (n, k) and out["weights"].shape == (n, k)
    assert np.allclose(out["weights"].sum(1), 1.0, atol=1e-3)
    assert set(np.unique(out["joints"])) <= {0, 1}


def test_polygons_as_lists_and_as_flat_arrays():
    pos, quads = grid(16)
    # The ordering's ties as set: on this bumpy grid, held to the mean
    # distance of cost order alone (the default), they would narrow away.
    as_lists = wildlod.simplify(pos, [list(q) for q in quads], ratio=0.25, quad_tolerance=float("inf"))
    assert isinstance(as_lists["faces"], list)
    assert all(len(f) in (3, 4) for f in as_lists["faces"])
    # Quads are kept where the simplifier can (Knodt 2024's ordering).
    assert sum(len(f) == 4 for f in as_lists["faces"]) > 0.5 * len(as_lists["faces"])
    flat = wildlod.simplify(pos, quads.reshape(-1), face_sizes=np.full(len(quads), 4), ratio=0.25,
                            quad_tolerance=float("inf"))
    assert flat["faces"].ndim == 1
    assert np.array_equal(flat["faces"], flat["indices"])
    # The same mesh in two spellings gives the same result.
    assert np.array_equal(flat["indices"], as_lists["indices"])
    check_faces(flat, {3, 4})
    # Mixed polygons: a pentagon among quads.
    polys = [list(q) for q in quads[1:]] + [[int(quads[0][0]), int(quads[0][1]), int(quads[0][2]), int(quads[0][3])]]
    out = wildlod.simplify(pos, polys, ratio=0.5)
    check_faces(out)


def test_options_reach_the_simplifier():
    pos, quads = grid(16)
    border = np.array([p for p in pos if p[0] in (0, 16) or p[1] in (0, 16)])

    def moved(out):
        """How far each border vertex is from the nearest output vertex
        (positions are rescaled inside, so equal means within rounding)."""
        p = out["positions"].astype(np.float64)
        return np.array([np.abs(p - b).max(1).min() for b in border])

    locked = wildlod.simplify(pos, quads, ratio=0.1, lock_borders=True)
    assert moved(locked).max() < 1e-5, "a border vertex moved although borders were locked"
    free = wildlod.simplify(pos, quads, ratio=0.1)
    assert moved(free).max() > 0.1
    # Classic QEM and the plain cost order take other collapses.
    default = wildlod.simplify(pos, quads, ratio=0.3)
    classic = wildlod.simplify(pos, quads, ratio=0.3, classic=True, no_quads=True)
    assert classic["report"]["output_triangles"] > 0
    assert not np.array_equal(classic["indices"], default["indices"])
    # A bool given as an option name that takes a number is a TypeError.
    with pytest.raises(TypeError):
        wildlod.simplify(pos, quads, ratio=0.3, uv_weight="heavy")


def test_vertex_weights_protect_heavy_vertices():
    # A flat grid with one small bump: at 1% (four triangles) plain QEM
    # flattens it, a heavy weight on its tip keeps most of it. (At 2%, ten
    # triangles, the square needs only two of them now that its flat border
    # stays exact, which leaves room for the bump either way.)
    pos, quads = grid(16)
    pos[:, 2] = 0
    tip = np.argmin(np.linalg.norm(pos[:, :2] - 8, axis=1))
    pos[tip, 2] = 0.3
    heavy = np.ones(len(pos), np.float32)
    heavy[tip] = 1e4
    light = wildlod.simplify(pos, quads, ratio=0.01)["positions"][:, 2].max()
    kept = wildlod.simplify(pos, quads, ratio=0.01, vertex_weights=heavy)["positions"][:, 2].max()
    assert kept > 0.15 and kept > 2 * light, (kept, light)


@pytest.mark.parametrize("call, fragment", [
    (lambda p, f: wildlod.simplify(p, f, ratio=1.5), "ratio must be between 0 and 1"),
    (lambda p, f: wildlod.simplify(p, f, error=-1.0), "error must be a non-negative"),
    (lambda p, f: wildlod.simplify(p, f + 10_000), "refers to vertex"),
    (lambda p, f: wildlod.simplify(p, f - 10_000), "negative entry"),
    (lambda p, f: wildlod.simplify(p, f.astype(float)), "must be integers"),
    (lambda p, f: wildlod.simplify(p[:, :2], f), "positions has shape"),
    (lambda p, f: wildlod.simplify(p, f[:, :2]), "faces has shape"),
    (lambda p, f: wildlod.simplify(p, f, uvs=p), "uvs has shape"),
    (lambda p, f: wildlod.simplify(p, f, uvs=p[:10, :2]), "one row per vertex"),
    (lambda p, f: wildlod.simplify(p, f, joints=np.zeros((len(p), 4), int)), "joints and weights"),
    (lambda p, f: wildlod.simplify(p, f, uv_weight=-2.0), "uv_weight must be a non-negative"),
    (lambda p, f: wildlod.simplify(p, f, max_normal_turn=0.0), "max_normal_turn must be in"),
    (lambda p, f: wildlod.simplify(p, f, seams="sometimes"), "seams must be"),
    (lambda p, f: wildlod.simplify(p, f.reshape(-1), face_sizes=[3] * (len(f) + 1)), "face sizes add up"),
    (lambda p, f: wildlod.simplify(np.where(p > 0.5, np.nan, p), f), "non-finite"),
])
def test_bad_input_raises_wildlod_error_naming_it(call, fragment):
    pos, faces, _, _ = torus(12, 8)
    with pytest.raises(wildlod.WildlodError) as e:
        call(pos, faces)
    assert isinstance(e.value, ValueError)
    assert fragment in str(e.value), str(e.value)


def test_unknown_option_is_a_type_error():
    pos, faces, _, _ = torus(12, 8)
    with pytest.raises(TypeError, match="unexpected option"):
        wildlod.simplify(pos, faces, virtual_raduis=0.1)


def test_two_threads_simplify_at_the_same_time():
    """The GIL is released during the work: the two calls' native intervals
    (each ends when its call returns and lasts its report's seconds) overlap,
    and a third Python thread keeps ticking while they run."""
    pos, quads = grid(150)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    wildlod.simplify(pos, tris[:100], ratio=0.5)  # warm up
    spans = {}
    ticks = []
    stop = threading.Event()
    barrier = threading.Barrier(2)

    def work(k):
        barrier.wait()
        out = wildlod.simplify(pos, tris, ratio=0.05, no_quads=True)
        end = time.perf_counter()
        spans[k] = (end - out["report"]["seconds"], end)

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    ticker = threading.Thread(target=tick)
    ticker.start()
    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    stop.set()
    ticker.join()
    (s0, e0), (s1, e1) = spans[0], spans[1]
    shorter = min(e0 - s0, e1 - s1)
    assert shorter > 0.1, f"each call should take a while to measure: {shorter:.3f} s"
    overlap = min(e0, e1) - max(s0, s1)
    assert overlap > 0.5 * shorter, f"calls ran one after the other: {spans}"
    # While both were inside the simplifier, Python code ran too.
    inside = [t for t in ticks if max(s0, s1) <= t <= min(e0, e1)]
    assert len(inside) >= 5, f"the ticker starved: {len(inside)} ticks in {overlap:.3f} s"
    gaps = np.diff([max(s0, s1)] + inside + [min(e0, e1)])
    assert gaps.max() < 0.5 * overlap, f"the ticker stalled for {gaps.max():.3f} s"


def test_refit_moves_vertices_not_faces():
    pos, tris, _, _ = torus()
    fitted = wildlod.simplify(pos, tris, ratio=0.2, no_quads=True)
    plain = wildlod.simplify(pos, tris, ratio=0.2, no_quads=True, refit_sweeps=0)
    assert np.array_equal(fitted["indices"], plain["indices"])
    assert not np.array_equal(fitted["positions"], plain["positions"])
    assert "refit_sweeps" in wildlod.option_names()


def test_hidden_twins_of_a_closed_surface_are_dropped_unless_kept():
    pos, tris, _, _ = torus()
    doubled = np.concatenate([tris, tris[:, ::-1]])
    out = wildlod.simplify(pos, doubled, ratio=0.5)
    # Half of the doubled count is the torus once: every face kept once.
    assert len(out["indices"]) == tris.size
    assert out["report"]["hidden_twins"] == len(tris)
    kept = wildlod.simplify(pos, doubled, ratio=0.5, keep_hidden_twins=True)
    assert kept["report"]["hidden_twins"] == 0
    assert "keep_hidden_twins" in wildlod.option_names()


def test_a_part_inside_a_closed_part_is_dropped_unless_kept():
    pos, tris, _, _ = torus()
    # A small torus inside the big one's tube, touching it nowhere.
    small, small_tris, _, _ = torus(n=24, m=12, big=0.15, small=0.05)
    both = np.concatenate([pos, small + [1.0, 0.0, 0.0]])
    faces = np.concatenate([tris, small_tris + len(pos)])
    out = wildlod.simplify(both, faces, ratio=0.5)
    assert out["report"]["enclosed_parts"] == 1
    # Every output vertex is on the big torus: none on the small one.
    p = out["positions"].astype(np.float64)
    tube = np.hypot(np.hypot(p[:, 0], p[:, 1]) - 1.0, p[:, 2])
    assert tube.min() > 0.3, tube.min()
    kept = wildlod.simplify(both, faces, ratio=0.5, keep_enclosed_parts=True)
    assert kept["report"]["enclosed_parts"] == 0
    assert "keep_enclosed_parts" in wildlod.option_names()


def test_quad_tie_factor_reaches_the_simplifier():
    # A grid of quads with a ridge: ties at the mesh's own scale (factor 1)
    # and the fixed distance alone (factor 0) order collapses differently,
    # and a negative factor is refused with the option's name.
    pos, quads = grid(24)
    pos[:, 2] = 0.3 * np.sin(pos[:, 0] * 0.7) * np.cos(pos[:, 1] * 0.5)
    own = wildlod.simplify(pos, quads, ratio=0.5, quad_tie_factor=1.0)
    fixed = wildlod.simplify(pos, quads, ratio=0.5, quad_tie_factor=0.0)
    assert not np.array_equal(own["positions"], fixed["positions"])
    with pytest.raises(ValueError, match="quad_tie_factor"):
        wildlod.simplify(pos, quads, ratio=0.5, quad_tie_factor=-1.0)
    assert "quad_tie_factor" in wildlod.option_names()


def test_quad_tolerance_reaches_the_simplifier():
    # A bumpy grid of quads at 10%: the full ties cost more mean distance
    # than the run without the ordering, so holding them to it (1: no more
    # than that) changes the output, and a tolerance below 1 is refused
    # with the option's name.
    pos, quads = grid(24)
    pos[:, 2] = 0.3 * np.sin(pos[:, 0] * 0.9) * np.cos(pos[:, 1] * 0.8)
    unheld = wildlod.simplify(pos, quads, ratio=0.1, quad_tolerance=float("inf"))
    held = wildlod.simplify(pos, quads, ratio=0.1, quad_tolerance=1.0)
    assert not np.array_equal(unheld["positions"], held["positions"])
    with pytest.raises(ValueError, match="quad_tolerance"):
        wildlod.simplify(pos, quads, ratio=0.1, quad_tolerance=0.5)
    assert "quad_tolerance" in wildlod.option_names()


def test_pinch_distance_reaches_the_simplifier():
    # Eight triangles are below what a torus can keep: capped, its pinches
    # compete once the rest gets costly; uncapped (0), they wait until
    # nothing else is left. A negative distance is refused by name.
    pos, tris, _, _ = torus()
    capped = wildlod.simplify(pos, tris, faces_target=8, no_quads=True)
    uncapped = wildlod.simplify(pos, tris, faces_target=8, no_quads=True, pinch_distance=0.0)
    assert not np.array_equal(capped["positions"], uncapped["positions"])
    with pytest.raises(ValueError, match="pinch_distance"):
        wildlod.simplify(pos, tris, faces_target=8, pinch_distance=-1.0)
    assert "pinch_distance" in wildlod.option_names()


def test_crease_settings_reach_the_simplifier():
    # A sheet folded at a right angle along x = 12 (a crease at the default
    # angle of 78 degrees), bumped so that no collapse is free: the
    # crease planes, the area swept against the crease and the angle that
    # finds it each change which collapses go first.
    pos, quads = grid(24)
    pos[:, 2] += np.abs(pos[:, 0] - 12.0)
    run = lambda **o: wildlod.simplify(pos, quads, ratio=0.1, no_quads=True, **o)["positions"]  # noqa: E731
    default = run()
    assert np.array_equal(default, run(crease_weight=0.25, crease_area_weight=1.0))
    assert not np.array_equal(default, run(crease_weight=0.0))
    assert not np.array_equal(default, run(crease_area_weight=0.0))
    # With the angle above the fold's 90 degrees, the fold is no crease:
    # both terms go.
    assert not np.array_equal(default, run(crease_angle=120.0))
    # The current faces rank the collapses of the fold as triangles (not
    # on inputs with quads, where Knodt's ordering decides).
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    run_tris = lambda **o: wildlod.simplify(pos, tris, ratio=0.1, **o)["positions"]  # noqa: E731
    with_current = run_tris()
    assert np.array_equal(with_current, run_tris(current_faces=1.0))
    assert not np.array_equal(with_current, run_tris(current_faces=0.0))
    assert np.array_equal(default, run(current_faces=0.0))
    for name, bad in [
        ("crease_weight", -1.0),
        ("crease_area_weight", -1.0),
        ("current_faces", -1.0),
        ("crease_angle", 180.0),
    ]:
        with pytest.raises(ValueError, match=name):
            wildlod.simplify(pos, quads, ratio=0.1, **{name: bad})
        assert name in wildlod.option_names()


def test_a_decal_is_lifted_off_a_simplified_floor_unless_no_layers():
    # A bumpy floor of quads and a decal: a 6 x 6 grid 0.02 above its
    # middle, facing the same way. At 10% the floor moves by more than the
    # gap; by default the decal is lifted to clear it, with no_layers it
    # is left where its own simplification put it.
    pos, quads = grid(24)
    pos[:, 2] = 0.4 * np.sin(pos[:, 0] * 0.7) * np.cos(pos[:, 1] * 0.5)
    dpos, dquads = grid(6)
    dpos[:, :2] += 9.0
    dpos[:, 2] = 0.4 * np.sin(dpos[:, 0] * 0.7) * np.cos(dpos[:, 1] * 0.5) + 0.02
    allpos = np.concatenate([pos, dpos])
    allquads = np.concatenate([quads, dquads + len(pos)])
    kept = wildlod.simplify(allpos, allquads, ratio=0.1, no_quads=True)
    sunk = wildlod.simplify(allpos, allquads, ratio=0.1, no_quads=True, no_layers=True)
    assert kept["report"]["layer_vertices"] > 0
    assert sunk["report"]["layer_vertices"] == 0
    assert np.array_equal(kept["indices"], sunk["indices"])
    moved = np.any(kept["positions"] != sunk["positions"], axis=1)
    # Only decal vertices move (the decal lies over x, y in [9, 15]; a lift
    # along its mean normal, which leans a little, moves them sideways a
    # little).
    xy = sunk["positions"][:, :2]
    inside = np.all((xy >= 8.9) & (xy <= 15.1), axis=1)
    assert moved.any() and np.all(inside[moved])
    assert "no_layers" in wildlod.option_names()

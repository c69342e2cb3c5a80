"""Branching grids in Python: gv.branching_grid() and gv.voronoi(..., coarsen=N) (docs/branching.md).

Factor 1 is the regular solve bit for bit; the per-copy results equal an independent Dijkstra (SciPy)
on the copy graph built from the returned links; the command line (`python -m geovoronoi voronoi
--coarsen N`, the tool's own code) writes the same bits as the API."""

import os
import subprocess
import sys

import numpy as np
import pytest

import geovoronoi as gv

scipy_sparse = pytest.importorskip("scipy.sparse")
csgraph = pytest.importorskip("scipy.sparse.csgraph")


def fingers(count=3, gap=1, width=5, length=20, palm=4, depth=4, rng=None):
    """[z, y, x] field: a palm (y < palm) and `count` fingers along y, `gap` empty columns apart."""
    nx = count * width + (count - 1) * gap
    f = np.zeros((depth, palm + length, nx), np.float32)
    f[:, :palm, :] = 150
    for i in range(count):
        x0 = i * (width + gap)
        f[:, palm:, x0:x0 + width] = 100 + 50 * i
    if rng is not None:
        f = np.where(f > 0, f * rng.uniform(0.5, 1.5, f.shape), 0).astype(np.float32)
    return f


def blobs(rng, shape=(10, 13, 11)):
    f = rng.uniform(1.0, 40.0, shape)
    f[rng.uniform(size=shape) < 0.3] = 0
    return f


def metric_weight(metric, length, a, b):
    if metric == "min_stiffness":
        return length / np.minimum(a, b)
    if metric == "mean_stiffness":
        return 2 * length / (a + b)
    if metric == "mean_cost":
        return length * (a + b) / 2
    return length


def copy_graph(g, metric):
    """The copy graph from the returned links alone: each link's length from its two cells' coarse
    positions (not from its direction index), its weight by the metric from the two stiffnesses."""
    n = g.copies
    src = np.repeat(np.arange(n), np.diff(g.link_begin))
    dst = g.link_copy
    cz, cy, cx = np.unravel_index(g.cell, g.coarse_shape)
    pos = np.stack([cz, cy, cx], 1).astype(np.float64) * np.asarray(g.coarse_spacing)
    length = np.sqrt(((pos[dst] - pos[src]) ** 2).sum(1))
    s = g.stiffness.astype(np.float64)
    w = metric_weight(metric, length, s[src], s[dst])
    assert np.all(w > 0)
    return scipy_sparse.csr_matrix((w, (src, dst)), shape=(n, n))


def check_against_dijkstra(d, metric):
    g = d.grid
    graph = copy_graph(g, metric)
    # links are symmetric
    assert (graph != graph.T).nnz == 0
    all_d = csgraph.dijkstra(graph, directed=True, indices=d.seed_copies)  # seeds x copies
    best = all_d.min(0)
    reach = np.isfinite(best)
    assert np.array_equal(np.isfinite(d.distance), reach)
    assert np.array_equal(d.label >= 0, reach)
    np.testing.assert_allclose(d.distance[reach], best[reach], rtol=2e-5, atol=0)
    # labels: exact where the nearest seed is clear (the second nearest further by more than rounding)
    srt = np.sort(all_d, 0)
    clear = reach.copy()
    if len(d.seed_copies) > 1:
        with np.errstate(invalid="ignore"):  # inf - inf where only one seed reaches a copy
            gap = np.where(np.isfinite(srt[1]), srt[1] - srt[0], np.inf)
        clear &= gap > 1e-4 * np.maximum(srt[0], 1)
    assert clear.sum() > 0.5 * reach.sum()
    assert np.array_equal(d.label[clear], all_d.argmin(0)[clear])
    # parents: each reached non-seed copy is reached from a linked copy of the same label
    for a in np.flatnonzero(reach)[:200]:
        p = d.parent[a]
        if a in d.seed_copies:
            assert p == -1
            continue
        assert d.label[p] == d.label[a]
        assert p in g.link_copy[g.link_begin[a]:g.link_begin[a + 1]]
    # the fine picture is the copies' values painted through fine_copy
    fc = g.fine_copy
    inside = fc >= 0
    assert np.array_equal(d.fine_label[inside], d.label[fc[inside]])
    assert np.array_equal(d.fine_distance[inside].view(np.uint32 if d.distance.dtype == np.float32 else np.uint64),
                          d.distance[fc[inside]].view(np.uint32 if d.distance.dtype == np.float32 else np.uint64))
    assert np.all(d.fine_label[~inside] == -1) and np.all(np.isinf(d.fine_distance[~inside]))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("metric,conn", [("min_stiffness", 26), ("uniform", 6), ("mean_stiffness", 18)])
def test_factor_one_is_the_regular_solve(rng, dtype, metric, conn):
    f = blobs(rng).astype(dtype)
    inside = np.argwhere(f > 0)
    seeds = inside[rng.choice(len(inside), 4, replace=False)]
    kw = dict(metric=metric, connectivity=conn, spacing=(1.5, 1.0, 0.5), origin=(1, 2, 3), backend="seq")
    reg = gv.voronoi(f, seeds, **kw)
    br = gv.voronoi(f, seeds, coarsen=1, **kw)
    assert isinstance(br, gv.BranchingDiagram) and br.grid.copies == int((f > 0).sum())
    assert br.distance.dtype == dtype and br.fine_distance.dtype == dtype
    u = np.uint32 if dtype == np.float32 else np.uint64
    assert np.array_equal(br.fine_distance.view(u), reg.distance.view(u))
    assert np.array_equal(br.fine_label, reg.label)
    assert np.array_equal(br.distance.view(u), reg.distance[f > 0].view(u))
    assert br.grid.coarse_shape == f.shape and br.grid.coarse_spacing == (1.5, 1.0, 0.5)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("metric,conn,factor", [("min_stiffness", 26, 4), ("mean_cost", 6, 3),
                                                ("uniform", 18, 2), ("mean_stiffness", 26, 3)])
def test_copies_equal_a_dijkstra_on_the_copy_graph(rng, dtype, metric, conn, factor):
    for f in (fingers(rng=rng).astype(dtype), blobs(rng).astype(dtype)):
        inside = np.argwhere(f > 0)
        seeds = inside[rng.choice(len(inside), 3, replace=False)]
        g0 = gv.branching_grid(f, factor, connectivity=conn)
        if len(set(int(g0.fine_copy[tuple(s)]) for s in seeds)) < len(seeds):
            seeds = seeds[:1]  # two seeds in one copy are refused (test_bad_inputs)
        d = gv.voronoi(f, seeds, metric=metric, connectivity=conn, coarsen=factor, spacing=(1.0, 2.0, 0.5))
        check_against_dijkstra(d, metric)
        if "thrust" in gv.backends():
            t = gv.voronoi(f, seeds, metric=metric, connectivity=conn, coarsen=factor, spacing=(1.0, 2.0, 0.5),
                           backend="thrust")
            assert np.array_equal(t.distance, d.distance) and np.array_equal(t.label, d.label)


def test_fingers_stay_apart():
    f = fingers(count=2)  # fingers x = 0..4 and 6..10, the gap x = 5 inside the coarse cells x = 4..7
    tip_a, palm_b, tip_b = (0, 23, 0), (0, 0, 10), (0, 23, 10)
    g = gv.branching_grid(f, 4)
    # the coarse cell spanning the gap holds two copies (one per finger)
    a, b = g.fine_copy[0, 23, 4], g.fine_copy[0, 23, 6]
    assert a != b and g.cell[a] == g.cell[b]
    d = gv.voronoi(f, [tip_a, palm_b], coarsen=4, metric="uniform")
    assert d.fine_label[tip_b] == 1 and d.fine_label[0, 23, 6] == 1 and d.fine_label[0, 23, 4] == 0
    one = gv.voronoi(f, [tip_a], coarsen=4, metric="uniform")
    assert one.fine_distance[tip_b] > 30  # down, across the palm, up (a glued cell: 4 or 8)
    # the same field coarsened regularly (a 4x4x4 cell is material where any of its voxels is) glues them
    cz, cy, cx = (np.asarray(f.shape) + 3) // 4
    padded = np.zeros((cz * 4, cy * 4, cx * 4), f.dtype)
    padded[:f.shape[0], :f.shape[1], :f.shape[2]] = f
    coarse = padded.reshape(cz, 4, cy, 4, cx, 4).max((1, 3, 5))
    glued = gv.voronoi(coarse, [(0, 5, 0)], metric="uniform", spacing=4.0)
    assert glued.distance[0, 5, 2] <= 8


def test_branching_grid_arrays():
    f = fingers(count=2, depth=3)
    g = gv.branching_grid(f, 4, connectivity=6, reduction="min", spacing=(1, 1, 2), origin=(0, 0, 10))
    assert g.factor == 4 and g.connectivity == 6 and g.reduction == "min"
    assert g.coarse_shape == (1, 6, 3) and g.coarse_spacing == (4.0, 4.0, 8.0)
    assert g.coarse_origin == (1.5, 1.5, 13.0)
    assert g.fine_copy.shape == f.shape and g.fine_copy.dtype == np.int64
    assert np.array_equal(np.unique(g.fine_copy[f > 0]), np.arange(g.copies))
    assert np.all(g.fine_copy[f <= 0] == -1)
    assert np.array_equal(np.bincount(g.fine_copy[f > 0], minlength=g.copies), g.voxel_count)
    for c in range(g.copies):
        assert g.stiffness[c] == f[g.fine_copy == c].min()
        assert g.cell_begin[g.cell[c]] <= c < g.cell_begin[g.cell[c] + 1]
        assert np.unravel_index(g.copy_voxel[c], f.shape) == tuple(np.argwhere(g.fine_copy == c)[0])
    assert g.link_begin[-1] == len(g.link_copy) == len(g.link_dir)
    h = gv.branching_grid(f, 4, reduction="harmonic")
    assert h.reduction == "harmonic" and h.connectivity == 26


def test_bad_inputs():
    f = fingers(count=2)
    for bad in (0, -1):
        with pytest.raises(ValueError, match="coarsening factor"):
            gv.branching_grid(f, bad)
        with pytest.raises(ValueError, match="coarsening factor"):
            gv.voronoi(f, [(0, 0, 0)], coarsen=bad)
    for bad in (2.5, "2", True):
        with pytest.raises(TypeError, match="coarsening factor must be an integer"):
            gv.voronoi(f, [(0, 0, 0)], coarsen=bad)
    with pytest.raises(ValueError, match="reduction"):
        gv.branching_grid(f, 2, reduction="median")
    with pytest.raises(ValueError, match=r"seed 1 at \(0, 10, 5\) lies in empty material"):
        gv.voronoi(f, [(0, 0, 0), (0, 10, 5)], coarsen=4)
    with pytest.raises(ValueError, match="same copy"):
        gv.voronoi(f, [(0, 0, 0), (0, 0, 1)], coarsen=4)
    with pytest.raises(ValueError, match="3D"):
        gv.voronoi(f[0], [(0, 0)], coarsen=2)
    with pytest.raises(ValueError, match="no material|material"):
        gv.branching_grid(np.zeros((4, 4, 4)), 2)


def test_command_line_writes_the_api_bits(tmp_path):
    """`python -m geovoronoi voronoi --coarsen 4` (the tool's code) against gv.voronoi(coarsen=4)."""
    rng = np.random.default_rng(5)
    f = fingers(count=3, rng=rng)
    spacing, origin = (2.0, 1.0, 0.75), (0.5, -1.0, 3.0)
    gv.write_image(tmp_path / "fingers.mhd", f, spacing, origin)
    seeds = np.array([[0, 23, 0], [3, 0, 16], [1, 20, 9]])  # z, y, x
    with open(tmp_path / "seeds.csv", "w") as fh:
        for z, y, x in seeds:
            fh.write(f"{x},{y},{z}\n")
    args = ["voronoi", "--stiffness", str(tmp_path / "fingers.mhd"), "--seeds", str(tmp_path / "seeds.csv"),
            "--coarsen", "4", "--reduction", "harmonic", "--metric", "mean_stiffness", "--connectivity", "18"]
    r = subprocess.run([sys.executable, "-m", "geovoronoi"] + args + ["--out", str(tmp_path / "py")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    d = gv.voronoi(f, seeds, coarsen=4, reduction="harmonic", metric="mean_stiffness", connectivity=18,
                   spacing=spacing, origin=origin)
    assert f"into {d.grid.copies} copies" in r.stdout
    dist, sp, org, _ = gv.read_image(tmp_path / "py" / "distance.mhd")
    label, *_ = gv.read_image(tmp_path / "py" / "label.mhd")
    assert sp == spacing and org == origin
    assert np.array_equal(dist.view(np.uint32), d.fine_distance.view(np.uint32))
    assert np.array_equal(label, d.fine_label)
    z = np.load(tmp_path / "py" / "copies.npz")
    assert np.array_equal(z["distance"].view(np.uint32), d.distance.view(np.uint32))
    for name in ("label", "parent"):
        assert np.array_equal(z[name], getattr(d, name)), name
    for name in ("cell", "stiffness", "voxel_count", "link_begin", "link_copy", "link_dir", "fine_copy"):
        assert np.array_equal(z[name], getattr(d.grid, name)), name
    assert tuple(z["coarse_shape"]) == d.grid.coarse_shape and int(z["factor"][0]) == 4
    # the C++ tool's binary, when there is one: the same bytes
    cli = os.environ.get("GEOVORONOI_CLI")
    if cli and os.access(cli, os.X_OK):
        c = subprocess.run([cli] + args + ["--out", str(tmp_path / "cli")], capture_output=True, text=True,
                           timeout=300)
        assert c.returncode == 0, c.stderr
        for name in ("distance.raw", "label.raw", "copies.npz", "labels.png", "voronoi.vti"):
            assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name


# ---- shape functions and cuts on branching grids ------------------------------------------------------


def _bits(a):
    return a.view(np.uint32 if a.dtype == np.float32 else np.uint64)


def _same_csr(a, b):
    a, b = a.tocsr(), b.tocsr()
    a.sort_indices()
    b.sort_indices()
    return (a.shape == b.shape and np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
            and np.array_equal(_bits(a.data), _bits(b.data)))


@pytest.mark.parametrize("method", ["distance_ratio", "sibson", "laplace"])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shape_functions_factor_one_are_the_regular_weights(rng, method, dtype):
    f = blobs(rng, shape=(6, 7, 8)).astype(dtype)
    inside = np.argwhere(f > 0)
    seeds = inside[rng.choice(len(inside), 4, replace=False)]
    kw = dict(method=method, k=3, connectivity=18, spacing=(1.5, 1.0, 0.5), backend="seq")
    reg = gv.shape_functions(f, seeds, **kw)
    br = gv.shape_functions(f, seeds, coarsen=1, **kw)
    assert isinstance(br, gv.BranchingWeights)
    assert _same_csr(br.fine, reg)
    # the copies are the material voxels in index order: their rows are the regular rows there
    assert _same_csr(br.weights, reg[np.flatnonzero(f.ravel() > 0)])
    assert br.node.shape == (br.diagram.grid.copies, 3) and br.fine_node.shape == f.shape + (3,)


@pytest.mark.parametrize("method", ["distance_ratio", "sibson", "laplace"])
def test_shape_functions_per_copy_and_painted(method):
    f = fingers(count=2)  # fingers x = 0..4 and 6..10; the gap x = 5 inside the coarse cells x = 4..7
    seeds = [(0, 23, 0), (0, 23, 10), (2, 0, 5)]  # left tip, right tip, palm
    w = gv.shape_functions(f, seeds, method=method, coarsen=4, metric="uniform")
    g = w.diagram.grid
    assert w.weights.shape == (g.copies, 3) and w.fine.shape == (f.size, 3)
    # every copy's row sums to 1; the fine images are the rows painted through fine_copy
    np.testing.assert_allclose(np.asarray(w.weights.sum(1)).ravel(), 1, rtol=1e-5)
    inside = g.fine_copy >= 0
    assert np.array_equal(w.fine_node[inside], w.node[g.fine_copy[inside]])
    assert np.array_equal(_bits(w.fine_weight[inside]), _bits(w.weight[g.fine_copy[inside]]))
    assert np.all(w.fine_node[~inside] == -1) and np.all(w.fine_weight[~inside] == 0)
    if "thrust" in gv.backends():
        t = gv.shape_functions(f, seeds, method=method, coarsen=4, metric="uniform", backend="thrust")
        assert _same_csr(t.fine, w.fine) and np.array_equal(t.node, w.node)
    if method != "distance_ratio":
        # natural neighbours on the copy graph: the left tip's node does not leak into the right finger
        right = np.zeros(f.shape, bool)
        right[:, 12:, 6:] = True
        dense = w.fine.toarray()[:, 0].reshape(f.shape)
        assert np.all(dense[right & inside] == 0)
        assert dense[0, 23, 0] == 1


def test_shape_functions_at_fine_voxels_and_world_points():
    f = fingers(count=2)
    seeds = [(0, 23, 0), (0, 23, 10), (2, 0, 5)]
    spacing, origin = (1.0, 0.5, 2.0), (3.0, -1.0, 0.0)
    full = gv.shape_functions(f, seeds, method="laplace", coarsen=4, spacing=spacing, origin=origin)
    pts = np.array([(0, 23, 1), (3, 20, 9), (1, 10, 5), (2, 2, 2)])  # (1, 10, 5): the gap, empty material
    at = gv.shape_functions(f, seeds, method="laplace", coarsen=4, points=pts, spacing=spacing, origin=origin)
    assert _same_csr(at, full.fine[np.ravel_multi_index(tuple(pts.T), f.shape)])
    assert at[[2]].nnz == 0
    # world=True: the seeds and the points are world points (each off its voxel centre by 0.2 voxel)
    def to_world(v):
        return np.asarray(origin) + np.asarray(v) * np.asarray(spacing) + 0.2 * np.asarray(spacing)

    aw, idx, wt = gv.shape_functions(f, to_world(seeds), method="laplace", coarsen=4, points=to_world(pts),
                                     world=True, spacing=spacing, origin=origin, fixed_k=True)
    assert _same_csr(aw, at) and idx.shape == (4, 4) and wt.shape == (4, 4)
    with pytest.raises(ValueError, match="outside"):
        gv.shape_functions(f, seeds, method="laplace", coarsen=4, points=[(0, 24, 0)])
    with pytest.raises(ValueError, match="outside the grid"):
        gv.shape_functions(f, seeds, method="laplace", coarsen=4, points=[(0.0, 100.0, 0.0)], world=True)


def test_cut_splits_copies():
    f = fingers(count=2)
    # a blade at x = 1.5, y from -1 to 10 through every slice: inside the coarse cells x = 0..3
    v = np.array([[-5, -1, 1.5], [-5, 10, 1.5], [10, 10, 1.5], [10, -1, 1.5]], float)  # z, y, x
    t = np.array([[0, 1, 2], [0, 2, 3]])
    cut = gv.cut_from_mesh(v, t, shape=f.shape, connectivity=26)
    assert len(cut) > 0
    seeds = [(0, 23, 0), (0, 0, 10)]
    before = gv.voronoi(f, seeds, coarsen=4, metric="uniform")
    after = gv.voronoi(f, seeds, coarsen=4, metric="uniform", cut=cut)
    assert after.grid.copies > before.grid.copies
    # behind the blade (x = 0, low y) the path from the left tip now runs around its top end
    assert after.fine_distance[0, 0, 0] > before.fine_distance[0, 0, 0]
    w = gv.shape_functions(f, seeds, method="sibson", coarsen=4, metric="uniform", cut=cut)
    assert w.diagram.grid.copies == after.grid.copies
    assert np.array_equal(_bits(w.diagram.distance), _bits(after.distance))
    with pytest.raises(ValueError, match="cut"):
        gv.voronoi(f[:, :20], [(0, 19, 0), (0, 0, 10)], coarsen=4, cut=cut)


def test_shape_functions_bad_inputs():
    f = fingers(count=2)
    seeds = [(0, 23, 0), (0, 0, 10)]
    d = gv.voronoi(f, seeds, coarsen=4)
    with pytest.raises(ValueError, match="not a diagram"):
        gv.shape_functions(f, d, method="sibson", coarsen=4)
    with pytest.raises(ValueError, match="coarsening factor"):
        gv.shape_functions(f, seeds, method="sibson", coarsen=0)
    with pytest.raises(ValueError, match="keep_state"):
        gv.shape_functions(f, seeds, method="distance_ratio", coarsen=4, keep_state=True)
    with pytest.raises(ValueError, match="empty material"):
        gv.shape_functions(f, [(0, 10, 5)], method="sibson", coarsen=4)
    with pytest.raises(ValueError, match="3D"):
        gv.shape_functions(f[0], [(0, 0)], method="sibson", coarsen=2)


def test_shape_command_line_writes_the_api_bits(tmp_path):
    """`python -m geovoronoi shape-functions --coarsen 4` (the tool's code) against the API."""
    f = fingers(count=2)
    gv.write_image(tmp_path / "fingers.mhd", f)
    seeds = np.array([[0, 23, 0], [2, 0, 5], [1, 20, 9]])  # z, y, x
    with open(tmp_path / "seeds.csv", "w") as fh:
        for z, y, x in seeds:
            fh.write(f"{x},{y},{z}\n")
    with open(tmp_path / "at.csv", "w") as fh:
        fh.write("0,23,0\n9,20,1\n")
    base = [sys.executable, "-m", "geovoronoi", "shape-functions", "--stiffness", str(tmp_path / "fingers.mhd"),
            "--seeds", str(tmp_path / "seeds.csv"), "--coarsen", "4", "--method", "sibson", "--nodes-per-voxel", "3"]
    r = subprocess.run(base + ["--out", str(tmp_path / "py")], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    w = gv.shape_functions(f, seeds, method="sibson", k=3, coarsen=4)
    z = np.load(tmp_path / "py" / "copy_weights.npz")
    assert np.array_equal(z["node"], w.node) and np.array_equal(_bits(z["weight"]), _bits(w.weight))
    assert np.array_equal(z["fine_copy"], w.diagram.grid.fine_copy)
    assert np.array_equal(z["seed_copy"], w.diagram.seed_copies) and int(z["k"][0]) == 3
    idx, *_ = gv.read_image(tmp_path / "py" / "indices.mhd")
    wt, *_ = gv.read_image(tmp_path / "py" / "weights.mhd")
    assert np.array_equal(idx.astype(np.int64) - 1, w.fine_node) and np.array_equal(_bits(wt), _bits(w.fine_weight))
    r = subprocess.run(base + ["--at", str(tmp_path / "at.csv"), "--out", str(tmp_path / "at")], capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    at = gv.shape_functions(f, seeds, method="sibson", k=3, coarsen=4, points=[(0, 23, 0), (1, 20, 9)])
    data = np.load(tmp_path / "at" / "weights_at_data.npy")
    assert np.array_equal(_bits(data), _bits(at.data))
    bad = subprocess.run(base + ["--backend", "cuda", "--out", str(tmp_path / "bad")], capture_output=True,
                         text=True, timeout=300)
    assert bad.returncode == 2 and "not available on branching grids" in bad.stderr


def test_update_after_a_cut_is_the_solve_on_the_cut_grid():
    f = fingers(count=2, rng=np.random.default_rng(3))
    blade = gv.cut_from_mesh(np.array([[-5, -1, 1.5], [-5, 10, 1.5], [10, 10, 1.5], [10, -1, 1.5]], float),
                             np.array([[0, 1, 2], [0, 2, 3]]), shape=f.shape, connectivity=18)
    second = gv.cut_from_mesh(np.array([[-5, 14, 7.5], [-5, 30, 7.5], [10, 30, 7.5], [10, 14, 7.5]], float),
                              np.array([[0, 1, 2], [0, 2, 3]]), shape=f.shape, connectivity=18)
    seeds = [(0, 23, 0), (3, 0, 10), (1, 20, 8)]
    for dtype in (np.float32, np.float64):
        g = f.astype(dtype)
        before = gv.voronoi(g, seeds, coarsen=4, connectivity=18, metric="mean_stiffness")
        after = gv.update(before, g, cut=blade)
        full = gv.voronoi(g, seeds, coarsen=4, connectivity=18, metric="mean_stiffness", cut=blade)
        assert after.grid.copies == full.grid.copies > before.grid.copies
        for name in ("distance", "fine_distance"):
            assert np.array_equal(_bits(getattr(after, name)), _bits(getattr(full, name))), name
        for name in ("label", "parent", "seed_copies", "fine_label"):
            assert np.array_equal(getattr(after, name), getattr(full, name)), name
        assert after.stats["changed"] > 0 and after.cut == blade and before.stats is None
        # a second cut on top of the first: the cuts accumulate
        again = gv.update(after, g, cut=second)
        both = gv.voronoi(g, seeds, coarsen=4, connectivity=18, metric="mean_stiffness", cut=blade | second)
        assert np.array_equal(_bits(again.distance), _bits(both.distance))
        assert np.array_equal(again.parent, both.parent) and again.grid.copies == both.grid.copies
    with pytest.raises(ValueError, match="cut= only"):
        gv.update(before, g, cut=blade, carved=[(0, 0, 0)])
    with pytest.raises(ValueError, match="takes a cut"):
        gv.update(before, g)

"""Cuts and incremental updates: cut_from_mesh / cut_from_polylines / read_mesh, voronoi(cut=),
update() against full solves and update_shape_functions() against shape_functions(), bit for bit,
and the errors of bad input."""

import numpy as np
import pytest
import scipy.sparse

import geovoronoi as gv

BACKENDS = gv.backends()


def field(shape, dtype=np.float32, seed=3):
    rng = np.random.default_rng(seed)
    return rng.uniform(0.5, 2.0, shape).astype(dtype)


def same(a, b):
    """Bitwise equal diagrams: distance bytes, labels, parents, seeds."""
    assert a.distance.dtype == b.distance.dtype
    assert a.distance.tobytes() == b.distance.tobytes()
    assert np.array_equal(a.label, b.label)
    if a.parent is not None and b.parent is not None:
        assert np.array_equal(a.parent, b.parent)
    assert np.array_equal(a.seeds, b.seeds)


def plane_x(x, shape, extent=None):
    """Two triangles spanning the plane at array x = x (world = index with unit spacing), over
    z, y in [lo, hi] (default: beyond the whole grid); vertices in array-axis order (z, y, x)."""
    lo, hi = (-1.0, float(max(shape)) + 1) if extent is None else extent
    v = np.array([[lo, lo, x], [lo, hi, x], [hi, hi, x], [hi, lo, x]])
    t = np.array([[0, 1, 2], [0, 2, 3]])
    return v, t


def same_csr(a, b):
    assert a.shape == b.shape
    assert np.array_equal(a.indptr, b.indptr)
    assert np.array_equal(a.indices, b.indices)
    assert a.data.dtype == b.data.dtype and a.data.tobytes() == b.data.tobytes()


# ---- making cuts --------------------------------------------------------------------------------


@pytest.mark.parametrize("conn", [6, 18, 26])
@pytest.mark.parametrize("backend", BACKENDS)
def test_a_mesh_plane_separates_the_two_halves(conn, backend):
    shape = (5, 6, 10)
    f = np.ones(shape, np.float32)
    cut = gv.cut_from_mesh(*plane_x(4.5, shape), shape=shape, connectivity=conn)
    assert len(cut) > 0 and cut.stats["primitives"] == 2
    d = gv.voronoi(f, [[2, 3, 1], [2, 3, 8]], cut=cut, connectivity=conn, backend=backend)
    x = np.arange(shape[2])
    assert np.all(d.label[..., x <= 4] == 0) and np.all(d.label[..., x >= 5] == 1)
    # one seed: the far side cannot be reached
    d1 = gv.voronoi(f, [[2, 3, 1]], cut=cut, connectivity=conn, backend=backend)
    assert np.all(d1.label[..., x >= 5] == -1) and np.all(np.isinf(d1.distance[..., x >= 5]))
    assert np.all(d1.label[..., x <= 4] == 0)
    assert d.cut is cut


def test_cut_edges_merge_and_equality():
    shape = (4, 5, 8)
    a = gv.cut_from_mesh(*plane_x(2.5, shape), shape=shape, connectivity=6)
    b = gv.cut_from_mesh(*plane_x(5.5, shape), shape=shape, connectivity=6)
    assert len(a) == 4 * 5 and len(b) == 4 * 5  # one x-edge per (z, y) column
    e = a.edges()
    u = np.unravel_index(e[:, 0], shape)
    v = np.unravel_index(e[:, 1], shape)
    assert np.all(u[2] == 2) and np.all(v[2] == 3) and np.all(u[0] == v[0]) and np.all(u[1] == v[1])
    m = a.merge(b)
    assert len(m) == 40 and len(a) == 20  # immutable
    assert (a | b) == m and m != a
    assert a == gv.cut_from_mesh(*plane_x(2.5, shape), shape=shape, connectivity=6)
    c26 = gv.cut_from_mesh(*plane_x(2.5, shape), shape=shape, connectivity=26)
    with pytest.raises(ValueError, match="different grids or connectivities"):
        a.merge(c26)


def test_world_coordinates_follow_spacing_and_origin():
    shape = (4, 5, 8)
    # x spacing 0.5, origin 1: the plane at world x = 2.25 lies between voxels 2 (2.0) and 3 (2.5)
    cut = gv.cut_from_mesh(*plane_x(2.25, shape, (-10.0, 10.0)), shape=shape, spacing=(1.0, 1.0, 0.5),
                           origin=(0.0, 0.0, 1.0), connectivity=6)
    e = cut.edges()
    assert len(e) == 20 and np.all(np.unravel_index(e[:, 0], shape)[2] == 2)


def test_polylines_separate_a_2d_grid():
    shape = (7, 9)
    line = np.array([[-1.0, 3.5], [8.0, 3.5]])  # (y, x): the vertical line x = 3.5
    for conn in (4, 8):
        cut = gv.cut_from_polylines([line], shape=shape, connectivity=conn)
        d = gv.voronoi(np.ones(shape), [[3, 0], [3, 8]], cut=cut, connectivity=conn)
        assert np.all(d.label[:, :4] == 0) and np.all(d.label[:, 4:] == 1)


@pytest.mark.parametrize("ext", ["stl", "obj"])
def test_read_mesh_returns_array_axis_order(tmp_path, ext):
    xyz = np.array([[4.5, -1.0, -1.0], [4.5, 9.0, -1.0], [4.5, 9.0, 9.0]])
    p = tmp_path / f"tri.{ext}"
    if ext == "stl":
        lines = ["solid t", " facet normal 1 0 0", "  outer loop"]
        lines += [f"   vertex {x} {y} {z}" for x, y, z in xyz]
        lines += ["  endloop", " endfacet", "endsolid t"]
    else:
        lines = [f"v {x} {y} {z}" for x, y, z in xyz] + ["f 1 2 3"]
    p.write_text("\n".join(lines) + "\n")
    v, t = gv.read_mesh(p)
    assert np.array_equal(v, xyz[:, ::-1]) and t.tolist() == [[0, 1, 2]]
    shape = (5, 6, 8)
    assert gv.cut_from_mesh(v, t, shape=shape) == gv.cut_from_mesh(xyz[:, ::-1], t, shape=shape)


def test_shape_functions_use_the_diagrams_cuts():
    shape = (4, 5, 8)
    f = field(shape)
    seeds = [[1, 1, 1], [2, 3, 6], [3, 4, 2]]
    cut = gv.cut_from_mesh(*plane_x(3.5, shape, (-1.0, 3.0)), shape=shape)
    d = gv.voronoi(f, seeds, cut=cut)
    w = gv.shape_functions(f, d, method="sibson", k=3)
    same_csr(w, gv.shape_functions(f, seeds, method="sibson", k=3, cut=cut))
    plain = gv.shape_functions(f, gv.voronoi(f, seeds), method="sibson", k=3)
    assert (w != plain).nnz > 0


# ---- update == full solve -----------------------------------------------------------------------


CASES = [((6, 7, 9), 6), ((6, 7, 9), 26), ((6, 7, 9), 18), ((11, 13), 8), ((11, 13), 4)]
SEEDS = {3: np.array([[0, 0, 0], [5, 6, 8], [2, 3, 4], [4, 1, 7]]), 2: np.array([[0, 0], [10, 12], [5, 6], [2, 11]])}


def blade(shape, conn, x=4.5):
    if len(shape) == 3:
        return gv.cut_from_mesh(*plane_x(x, shape, (-1.0, 3.6)), shape=shape, connectivity=conn)
    return gv.cut_from_polylines([np.array([[-1.0, x], [6.5, x]])], shape=shape, connectivity=conn)


@pytest.mark.parametrize("shape,conn", CASES)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_update_after_a_cut_equals_a_full_solve(shape, conn, dtype):
    f = field(shape, dtype)
    s = SEEDS[len(shape)]
    d = gv.voronoi(f, s, connectivity=conn, parent=True)
    cut = blade(shape, conn)
    u = gv.update(d, f, cut=cut)
    same(u, gv.voronoi(f, s, connectivity=conn, cut=cut, parent=True))
    assert u.cut == cut and u.parent is not None and u.stats["invalidated"] > 0
    assert d.cut is None  # the diagram before is unchanged


@pytest.mark.parametrize("shape,conn", CASES)
def test_update_after_carving_adding_and_restiffening(shape, conn):
    rng = np.random.default_rng(5)
    f = field(shape)
    s = SEEDS[len(shape)]
    box = tuple(slice(1, 3) for _ in shape)
    # carve a box
    g = f.copy()
    g[box] = 0
    d = gv.voronoi(f, s, connectivity=conn, parent=True)
    carved = np.zeros(shape, bool)
    carved[box] = True
    u = gv.update(d, g, carved=carved)
    same(u, gv.voronoi(g, s, connectivity=conn, parent=True))
    # add it back (index-array form)
    u2 = gv.update(u, f, added=np.argwhere(carved))
    same(u2, gv.voronoi(f, s, connectivity=conn, parent=True))
    # restiffen random voxels, stiffer and softer
    h = f.copy()
    idx = rng.integers(0, np.array(shape), (7, len(shape)))
    h[tuple(idx.T)] = rng.uniform(0.1, 5.0, 7).astype(h.dtype)
    u3 = gv.update(d, h, restiffened=idx)
    same(u3, gv.voronoi(h, s, connectivity=conn, parent=True))


@pytest.mark.parametrize("shape,conn", CASES)
def test_update_after_node_edits(shape, conn):
    f = field(shape)
    s = SEEDS[len(shape)]
    d = gv.voronoi(f, s, connectivity=conn, parent=True)
    nd = len(shape)
    v1, v2 = (3,) * nd, (1,) * (nd - 1) + (2,)
    u = gv.update(d, f, nodes=[("add", v1)])
    same(u, gv.voronoi(f, np.vstack([s, [v1]]), connectivity=conn, parent=True))
    u = gv.update(d, f, nodes=[("add", v1, 1)])
    same(u, gv.voronoi(f, np.vstack([s[:1], [v1], s[1:]]), connectivity=conn, parent=True))
    u = gv.update(d, f, nodes=[("remove", 2)])
    same(u, gv.voronoi(f, np.delete(s, 2, axis=0), connectivity=conn, parent=True))
    u = gv.update(d, f, nodes=[("move", 1, v2)])
    t = s.copy()
    t[1] = v2
    same(u, gv.voronoi(f, t, connectivity=conn, parent=True))


@pytest.mark.parametrize("shape,conn", [((6, 7, 9), 26), ((11, 13), 8)])
def test_a_sequence_of_mixed_updates(shape, conn):
    f = field(shape, np.float64)
    s = SEEDS[len(shape)]
    d = gv.voronoi(f, s, connectivity=conn, parent=True)
    # 1. a cut
    c1 = blade(shape, conn, 4.5)
    d = gv.update(d, f, cut=c1)
    # 2. carve a voxel and move node 0, in one change
    nd = len(shape)
    g = f.copy()
    v = (1,) * nd
    g[v] = np.nan
    d = gv.update(d, g, carved=[v], nodes=[("move", 0, (0,) * (nd - 1) + (1,))])
    s2 = s.copy()
    s2[0] = (0,) * (nd - 1) + (1,)
    # 3. a second cut and a new node
    c2 = blade(shape, conn, 6.5)
    d = gv.update(d, g, cut=c2, nodes=[("add", (2,) * nd)])
    s3 = np.vstack([s2, [(2,) * nd]])
    assert d.cut == c1.merge(c2)
    same(d, gv.voronoi(g, s3, connectivity=conn, cut=c1 | c2, parent=True))
    # and every backend's full solve agrees
    for b in BACKENDS:
        same(d, gv.voronoi(g, s3, connectivity=conn, cut=c1 | c2, parent=True, backend=b))


def test_update_with_a_mask_keeps_it():
    shape = (6, 7, 9)
    f = field(shape)
    mask = np.ones(shape, bool)
    mask[:, 2, :] = False
    mask[:, 2, 0] = True
    s = SEEDS[3]
    d = gv.voronoi(f, s, mask=mask, parent=True)
    cut = blade(shape, 26)
    same(gv.update(d, f, cut=cut), gv.voronoi(f, s, mask=mask, cut=cut, parent=True))


# ---- update_shape_functions == shape_functions ---------------------------------------------------


@pytest.mark.parametrize("method", gv.METHODS)
@pytest.mark.parametrize("shape,conn", [((5, 6, 8), 26), ((5, 6, 8), 6), ((9, 11), 8)])
def test_update_shape_functions_equals_shape_functions(method, shape, conn):
    f = field(shape)
    s = SEEDS[len(shape)]
    s = np.minimum(s, np.array(shape) - 1)
    d = gv.voronoi(f, s, connectivity=conn, parent=True)
    w = gv.shape_functions(f, d, method=method, k=3, fixed_k=True)
    cut = blade(shape, conn, 3.5)
    u = gv.update(d, f, cut=cut)
    # the change recorded by update(), the fixed-K triple in, the triple out
    w2, st = gv.update_shape_functions(w, d, u, f, method=method, k=3, fixed_k=True, stats=True)
    ref = gv.shape_functions(f, u, method=method, k=3, fixed_k=True)
    same_csr(w2[0], ref[0])
    assert np.array_equal(w2[1], ref[1]) and w2[2].tobytes() == ref[2].tobytes()
    assert 0 < st["recomputed"] <= st["rows"]
    # the CSR alone in, the change given explicitly, a second change (carve + node move) on top
    g = f.copy()
    nd = len(shape)
    g[(2,) * nd] = 0
    u2 = gv.update(u, g, carved=[(2,) * nd], nodes=[("move", 2, (1,) * nd)])
    w3 = gv.update_shape_functions(ref[0], u, u2, g, method=method, k=3, carved=[(2,) * nd],
                                   nodes=[("move", 2, (1,) * nd)])
    same_csr(w3, gv.shape_functions(g, u2, method=method, k=3))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("backend", BACKENDS)
def test_distance_ratio_with_its_state_kept(dtype, backend):
    """keep_state / state=: the same weights as a full computation, through a sequence of a cut, a
    field edit, an appended and a moved node (repaired), a removed node (every row recomputed, the
    searches kept anew) and a cut, and the state is checked against the diagram it belongs to."""
    shape = (6, 9, 12)
    f = field(shape, dtype)
    s = np.minimum(SEEDS[3], np.array(shape) - 1)
    d = gv.voronoi(f, s, parent=True, backend=backend)
    plain = gv.shape_functions(f, d, method="distance_ratio", k=3, backend=backend)
    w, st = gv.shape_functions(f, d, method="distance_ratio", k=3, keep_state=True, backend=backend)
    assert isinstance(st, gv.ShapeState) and st.nbytes > 0 and "MB" in repr(st)
    same_csr(w, plain)
    # a cut: the kept searches are repaired, fewer rows than all recomputed
    u = gv.update(d, f, cut=blade(shape, 26, 5.5))
    w2, st2, info = gv.update_shape_functions(w, d, u, f, method="distance_ratio", k=3, state=st, stats=True,
                                              backend=backend)
    same_csr(w2, gv.shape_functions(f, u, method="distance_ratio", k=3))
    assert isinstance(st2, gv.ShapeState) and st2 is not st
    assert not info["full"] and info["recomputed"] < info["rows"]
    # the same update without the state gives the same weights
    same_csr(gv.update_shape_functions(w, d, u, f, method="distance_ratio", k=3, backend=backend), w2)
    # a field edit on top, then a node edit (every row recomputed, the searches kept anew)
    g = f.copy()
    g[3, 4, 6] *= 3
    u2 = gv.update(u, g, restiffened=[(3, 4, 6)])
    w3, st3 = gv.update_shape_functions(w2, u, u2, g, method="distance_ratio", k=3, state=st2, backend=backend)
    same_csr(w3, gv.shape_functions(g, u2, method="distance_ratio", k=3))
    u3 = gv.update(u2, g, nodes=[("add", (1, 1, 1))])
    w4, st4, info4 = gv.update_shape_functions(w3, u2, u3, g, method="distance_ratio", k=3, state=st3, stats=True,
                                               backend=backend)
    same_csr(w4, gv.shape_functions(g, u3, method="distance_ratio", k=3))
    assert w4.shape[1] == len(s) + 1 and not info4["full"]
    u4 = gv.update(u3, g, nodes=[("move", 0, (1, 2, 2))])
    w5, st5, info5 = gv.update_shape_functions(w4, u3, u4, g, method="distance_ratio", k=3, state=st4, stats=True,
                                               backend=backend)
    same_csr(w5, gv.shape_functions(g, u4, method="distance_ratio", k=3))
    assert not info5["full"]
    u5 = gv.update(u4, g, nodes=[("remove", 1)])
    w6, st6, info6 = gv.update_shape_functions(w5, u4, u5, g, method="distance_ratio", k=3, state=st5, stats=True,
                                               backend=backend)
    same_csr(w6, gv.shape_functions(g, u5, method="distance_ratio", k=3))
    assert info6["full"] and info6["recomputed"] == info6["rows"]
    u6 = gv.update(u5, g, cut=blade(shape, 26, 8.5))
    w7 = gv.update_shape_functions(w6, u5, u6, g, method="distance_ratio", k=3, state=st6, backend=backend)[0]
    same_csr(w7, gv.shape_functions(g, u6, method="distance_ratio", k=3))
    # a state belongs to its diagram, to Distance Ratio and to the whole grid
    with pytest.raises(ValueError, match="another diagram"):
        gv.update_shape_functions(w2, u, u2, g, method="distance_ratio", k=3, state=st)
    with pytest.raises(ValueError, match="distance_ratio"):
        gv.update_shape_functions(w, d, u, f, method="sibson", k=3, state=st)
    with pytest.raises(TypeError, match="ShapeState"):
        gv.update_shape_functions(w, d, u, f, method="distance_ratio", k=3, state=object())
    with pytest.raises(ValueError, match="keep_state"):
        gv.shape_functions(f, d, method="sibson", k=3, keep_state=True)
    with pytest.raises(ValueError, match="keep_state"):
        gv.shape_functions(f, s, method="distance_ratio", k=3, keep_state=True)
    with pytest.raises(ValueError, match="keep_state"):
        gv.shape_functions(f, d, method="distance_ratio", k=3, points=[[1, 1, 1]], keep_state=True)


@pytest.mark.parametrize("method", ["distance_ratio", "sibson"])
def test_update_shape_functions_at_points(method):
    shape = (5, 6, 8)
    f = field(shape)
    s = np.minimum(SEEDS[3], np.array(shape) - 1)
    pts = np.array([[0, 0, 0], [2, 3, 4], [4, 5, 7], [1, 2, 3], [3, 3, 5]])
    d = gv.voronoi(f, s, parent=True)
    w = gv.shape_functions(f, d, method=method, k=2, points=pts)
    u = gv.update(d, f, cut=blade(shape, 26, 3.5))
    w2 = gv.update_shape_functions(w, d, u, f, method=method, k=2, points=pts)
    same_csr(w2, gv.shape_functions(f, u, method=method, k=2, points=pts))


# ---- bad input -----------------------------------------------------------------------------------


def test_bad_inputs_raise_with_a_message(tmp_path):
    shape = (5, 6, 8)
    f = field(shape)
    s = np.minimum(SEEDS[3], np.array(shape) - 1)
    d = gv.voronoi(f, s)
    cut = blade(shape, 26)
    with pytest.raises(ValueError, match="parent=True"):
        gv.update(d, f, cut=cut)
    dp = gv.voronoi(f, s, parent=True)
    with pytest.raises(ValueError, match="still inside the domain"):
        gv.update(dp, f, carved=[(1, 1, 1)])
    with pytest.raises(ValueError, match="carved voxel 0 at \\(9, 1, 1\\) lies outside"):
        gv.update(dp, f, carved=[(9, 1, 1)])
    with pytest.raises(ValueError, match="connectivity 26, the solve uses 6"):
        gv.voronoi(f, s, connectivity=6, cut=cut)
    with pytest.raises(ValueError, match="shape"):
        gv.voronoi(field((5, 6, 9)), s, cut=cut)
    with pytest.raises(ValueError, match="spacing"):
        gv.voronoi(f, s, cut=cut, spacing=2.0)
    with pytest.raises(TypeError, match="Cut"):
        gv.voronoi(f, s, cut="blade")
    with pytest.raises(ValueError, match="node position 7"):
        gv.update(dp, f, nodes=[("remove", 7)])
    with pytest.raises(ValueError, match="unknown kind 'swap'"):
        gv.update(dp, f, nodes=[("swap", 0)])
    with pytest.raises(ValueError, match="outside the array"):
        gv.update(dp, f, nodes=[("add", (0, 0, 99))])
    with pytest.raises(ValueError, match="share|two nodes|seed"):
        gv.update(dp, f, nodes=[("add", tuple(s[0]))])
    with pytest.raises(ValueError, match="mask has shape"):
        gv.update(dp, f, restiffened=np.zeros((2, 2), bool))
    with pytest.raises(ValueError, match="not finite"):
        gv.cut_from_mesh([[0, 0, np.nan], [0, 1, 0], [1, 0, 0]], [[0, 1, 2]], shape=shape)
    with pytest.raises(ValueError, match="triangle 0 refers to vertex 5"):
        gv.cut_from_mesh([[0, 0, 0], [0, 1, 0], [1, 0, 0]], [[0, 1, 5]], shape=shape)
    with pytest.raises(ValueError, match="vertices must be an \\(n, 3\\)"):
        gv.cut_from_mesh([[0, 0], [0, 1]], [[0, 1, 0]], shape=shape)
    with pytest.raises(OSError, match="missing.stl"):
        gv.read_mesh(tmp_path / "missing.stl")
    (tmp_path / "m.ply").write_text("ply\n")
    with pytest.raises(OSError, match="unknown mesh format"):
        gv.read_mesh(tmp_path / "m.ply")
    u = gv.update(dp, f, cut=cut)
    w = gv.shape_functions(f, dp, method="distance_ratio", k=2)
    with pytest.raises(ValueError, match="more than k=1"):
        gv.update_shape_functions(w, dp, u, f, method="distance_ratio", k=1)
    with pytest.raises(ValueError, match="cuts are not"):
        gv.update_shape_functions(w, dp, u, f, method="distance_ratio", k=2, carved=np.zeros(shape, bool))
    with pytest.raises(ValueError, match="float64"):
        gv.update(dp, f.astype(np.float64), cut=cut)
    # method, k and batch_size: the same checks and messages as shape_functions (one helper)
    for kw, error, text in ((dict(method="natural"), ValueError, "unknown method 'natural'"),
                            (dict(method=3), TypeError, "method must be a string"),
                            (dict(k=0), ValueError, "k must be >= 1"),
                            (dict(k=2.0), TypeError, "k must be an integer"),
                            (dict(batch_size=0), ValueError, "batch_size must be >= 1"),
                            (dict(batch_size="8"), TypeError, "batch_size must be an integer")):
        args = dict(dict(method="distance_ratio", k=2), **kw)
        with pytest.raises(error, match=text):
            gv.update_shape_functions(w, dp, u, f, **args)
        with pytest.raises(error, match=text):
            gv.shape_functions(f, dp, **args)


def test_update_shape_functions_reports_progress_and_cancels():
    shape = (5, 6, 8)
    f = field(shape)
    s = np.minimum(SEEDS[3], np.array(shape) - 1)
    d = gv.voronoi(f, s, parent=True)
    w = gv.shape_functions(f, d, method="sibson", k=2)
    u = gv.update(d, f, cut=blade(shape, 26, 3.5))
    steps = []
    gv.update_shape_functions(w, d, u, f, method="sibson", k=2, progress=steps.append)
    assert steps and abs(sum(steps) - 100.0) < 1e-9

    class Stop(Exception):
        pass

    def stop(_):
        raise Stop()

    with pytest.raises(Stop):
        gv.update_shape_functions(w, d, u, f, method="sibson", k=2, progress=stop, batch_size=1)

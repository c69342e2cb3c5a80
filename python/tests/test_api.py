"""The Python API: zero-copy input, dtypes, parents, world seeds, shape functions, interpolation and
every bad input."""

import numpy as np
import pytest
import scipy.sparse

import geovoronoi as gv
from geovoronoi import _geovoronoi as ext


def field3(dtype=np.float32, shape=(6, 7, 8)):
    rng = np.random.default_rng(7)
    return rng.uniform(1.0, 3.0, shape).astype(dtype)


SEEDS3 = np.array([[0, 0, 0], [5, 6, 7], [2, 3, 4]])


# ---- zero copy ----------------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_c_contiguous_field_is_not_copied(dtype):
    f = field3(dtype)
    d = gv.voronoi(f, SEEDS3, backend="seq")
    assert ext._last_field_address() == f.ctypes.data
    assert d.distance.dtype == dtype
    gv.shape_functions(f, d, method="distance_ratio", backend="seq")
    assert ext._last_field_address() == f.ctypes.data


def test_read_only_field_is_not_copied():
    f = field3()
    f.setflags(write=False)
    gv.voronoi(f, SEEDS3, backend="seq")
    assert ext._last_field_address() == f.ctypes.data


def test_non_contiguous_field_is_copied_and_gives_the_same_result():
    big = field3(np.float64, (6, 7, 16))
    view = big[:, :, ::2]
    assert not view.flags.c_contiguous
    d = gv.voronoi(view, SEEDS3, backend="seq")
    assert ext._last_field_address() != view.ctypes.data
    ref = gv.voronoi(np.ascontiguousarray(view), SEEDS3, backend="seq")
    assert np.array_equal(d.distance, ref.distance) and np.array_equal(d.label, ref.label)


def test_results_are_views_of_library_memory():
    d = gv.voronoi(field3(), SEEDS3, backend="seq", parent=True)
    for a in (d.distance, d.label, d.parent):
        assert not a.flags.owndata and a.flags.c_contiguous
    assert d.label.dtype == np.int32 and d.parent.dtype == np.int64
    distance = d.distance
    del d
    assert np.isfinite(distance).all()  # still valid after the diagram is gone


def test_integer_field_becomes_float64():
    d = gv.voronoi(np.ones((5, 6), np.int16), [[0, 0]], backend="seq")
    assert d.distance.dtype == np.float64
    assert d.distance[0, 5] == 5.0


def test_big_endian_field():
    f = field3(np.float64).astype(">f8")
    d = gv.voronoi(f, SEEDS3, backend="seq")
    ref = gv.voronoi(f.astype("<f8"), SEEDS3, backend="seq")
    assert np.array_equal(d.distance, ref.distance)


# ---- semantics ------------------------------------------------------------------------------------


def test_axis_order_and_spacing():
    f = np.ones((3, 4, 5), np.float64)
    d = gv.voronoi(f, [[0, 0, 0]], spacing=(3.0, 2.0, 1.0), connectivity=6, metric="uniform", backend="seq")
    assert d.distance[0, 0, 4] == 4.0  # along x (last axis), spacing 1
    assert d.distance[0, 3, 0] == 6.0  # along y, spacing 2
    assert d.distance[2, 0, 0] == 6.0  # along z (first axis), spacing 3
    assert d.seeds.tolist() == [[0, 0, 0]]


def test_world_seeds_round_to_the_nearest_voxel():
    f = np.ones((4, 10), np.float32)
    d = gv.voronoi(f, [[2.2, 15.9]], world=True, spacing=(1.0, 2.0), origin=(1.0, -2.0), backend="seq")
    assert d.seeds.tolist() == [[1, 9]]
    assert d.label[1, 9] == 0 and d.distance[1, 9] == 0


def test_world_seeds_through_the_orientation():
    # a 2D grid whose array axis 0 (y) points along world x and axis 1 (x) along world -y
    f = np.ones((6, 8), np.float32)
    rot = np.array([[0.0, -1.0], [1.0, 0.0]])
    spacing, origin = (2.0, 0.5), (10.0, -3.0)
    idx = np.array([[1, 7], [4, 2], [5, 0]])
    world = np.asarray(origin) + (rot @ (idx * np.asarray(spacing)).T).T
    d = gv.voronoi(f, world + 0.1, world=True, spacing=spacing, origin=origin, orientation=rot, backend="seq")
    assert d.seeds.tolist() == idx.tolist()
    assert np.array_equal(d.orientation, rot)
    # without the orientation the same points miss the grid
    with pytest.raises(ValueError, match="outside"):
        gv.voronoi(f, world, world=True, spacing=spacing, origin=origin, backend="seq")
    # points too, from the diagram's orientation; a different orientation than the diagram's is refused
    w = gv.shape_functions(f, d, method="sibson", points=world[:2], world=True, backend="seq")
    full = gv.shape_functions(f, d, method="sibson", backend="seq")
    rows = np.ravel_multi_index(tuple(idx[:2].T), f.shape)
    assert np.array_equal(w.toarray(), full.toarray()[rows])
    with pytest.raises(ValueError, match="orientation differs"):
        gv.shape_functions(f, d, method="sibson", orientation=np.eye(2))


def test_orientation_round_trips_through_vti(tmp_path):
    rot = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    gv.write_vti(tmp_path / "a.vti", {"x": np.zeros((2, 3, 4), np.float32)}, orientation=rot)
    text = (tmp_path / "a.vti").read_text()
    assert 'Direction="-1 0 0 0 0 1 0 1 0"' in text, text[:400]


def test_parents_lead_to_the_seeds():
    f = field3(np.float64)
    d = gv.voronoi(f, SEEDS3, backend="seq", parent=True)
    flat_label = d.label.ravel()
    parent = d.parent.ravel()
    seeds_flat = set(np.ravel_multi_index(tuple(SEEDS3.T), f.shape).tolist())
    for v in range(f.size):
        u, steps = v, 0
        while parent[u] >= 0:
            assert flat_label[parent[u]] == flat_label[v]
            u = parent[u]
            steps += 1
            assert steps <= f.size
        assert u in seeds_flat


def test_mask_marks_voxels_outside():
    f = np.ones((5, 5), np.float32)
    mask = np.ones((5, 5), bool)
    mask[:, 2] = False
    d = gv.voronoi(f, [[0, 0]], mask=mask, connectivity=8, backend="seq")
    assert np.all(d.label[:, 2] == -1) and np.all(np.isinf(d.distance[:, 2]))
    assert np.all(d.label[:, 3:] == -1)  # cut off by the masked column
    assert f[0, 2] == 1.0  # the caller's field is untouched


def test_progress_reports_completion():
    got = []
    gv.voronoi(field3(), SEEDS3, backend="seq", progress=got.append)
    assert sum(got) == pytest.approx(100.0)


# ---- shape functions -------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["distance_ratio", "sibson", "laplace"])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_shape_functions_partition_of_unity_and_delta(method, dtype):
    f = field3(dtype)
    d = gv.voronoi(f, SEEDS3, backend="seq")
    w, idx, wt = gv.shape_functions(f, d, method=method, k=3, backend="seq", fixed_k=True)
    assert isinstance(w, scipy.sparse.csr_array)
    assert w.shape == (f.size, 3) and w.dtype == dtype
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=1e-5)
    for i, s in enumerate(SEEDS3):
        row = w[[np.ravel_multi_index(tuple(s), f.shape)]].toarray()[0]
        assert row[i] == 1.0 and row.sum() == 1.0
    assert idx.shape == f.shape + (3,) and wt.shape == f.shape + (3,)
    dense = w.toarray()
    flat_idx, flat_wt = idx.reshape(f.size, 3), wt.reshape(f.size, 3)
    for v in range(0, f.size, 7):
        for s in range(3):
            if flat_idx[v, s] >= 0:
                assert dense[v, flat_idx[v, s]] == flat_wt[v, s]
    # interpolation: both layouts agree, nodal values are reproduced at the nodes
    values = np.array([[1.0, 0.0], [0.0, 2.0], [3.0, 3.0]])
    u = gv.interpolate(w, values, shape=f.shape)
    u2 = gv.interpolate((idx, wt), values)
    assert u.shape == f.shape + (2,)
    np.testing.assert_allclose(u, u2, rtol=1e-5)
    for i, s in enumerate(SEEDS3):
        np.testing.assert_allclose(u[tuple(s)], values[i], rtol=1e-6)


def test_shape_functions_from_seeds_equal_from_diagram():
    f = field3()
    a = gv.shape_functions(f, SEEDS3, method="sibson", backend="seq")
    b = gv.shape_functions(f, gv.voronoi(f, SEEDS3, backend="seq"), method="sibson", backend="seq")
    assert (a != b).nnz == 0


@pytest.mark.parametrize("method", ["distance_ratio", "sibson", "laplace"])
def test_shape_functions_at_points_are_rows_of_the_full_result(method):
    f = field3()
    full, idx, wt = gv.shape_functions(f, SEEDS3, method=method, backend="seq", fixed_k=True)
    pts = np.array([[1, 2, 3], [5, 6, 7], [0, 1, 0], [5, 6, 7]])  # a repeated point gives the same row twice
    w, pidx, pwt = gv.shape_functions(f, SEEDS3, method=method, points=pts, backend="seq", fixed_k=True)
    assert w.shape == (len(pts), len(SEEDS3))
    rows = np.ravel_multi_index(tuple(pts.T), f.shape)
    assert np.array_equal(w.toarray(), full.toarray()[rows])
    assert np.array_equal(pidx, idx.reshape(f.size, -1)[rows])
    assert np.array_equal(pwt, wt.reshape(f.size, -1)[rows])


def test_shape_functions_backends_bitwise_equal():
    if "thrust" not in gv.backends():
        pytest.skip("the thrust backend is not built into this package")
    f = field3()
    a = gv.shape_functions(f, SEEDS3, method="sibson", backend="seq")
    b = gv.shape_functions(f, SEEDS3, method="sibson", backend="thrust", threads=2)
    assert np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
    assert np.array_equal(a.data.view(np.uint32), b.data.view(np.uint32))


def test_auto_backend_follows_the_per_problem_rule():
    """backend="auto" picks as the C++ tool's default does: a solve on a small domain runs on seq
    whatever the threads, on a domain of 2**18 voxels on thrust with two threads and seq with one;
    shape functions run on thrust with two threads at any size, on seq with one."""
    if "thrust" not in gv.backends():
        pytest.skip("the thrust backend is not built into this package: auto is always seq")
    small = field3()
    gv.voronoi(small, SEEDS3, threads=2)
    assert ext._last_backend() == "seq"
    gv.shape_functions(small, SEEDS3, method="distance_ratio", threads=2)
    assert ext._last_backend() == "thrust"
    gv.shape_functions(small, SEEDS3, method="sibson", threads=1)
    assert ext._last_backend() == "seq"
    big = np.ones((4, 256, 256), np.float32)  # 2**18 voxels, all inside
    seeds = np.array([[0, 0, 0], [3, 255, 255]])
    d1 = gv.voronoi(big, seeds, threads=1)
    assert ext._last_backend() == "seq"
    d2 = gv.voronoi(big, seeds, threads=2)
    assert ext._last_backend() == "thrust"
    assert np.array_equal(d1.label, d2.label)
    assert np.array_equal(d1.distance.view(np.uint32), d2.distance.view(np.uint32))
    gv.voronoi(big, seeds, backend="seq")
    assert ext._last_backend() == "seq"


def test_shape_functions_with_masked_diagram():
    f = field3()
    mask = np.ones(f.shape, bool)
    mask[3] = False
    d = gv.voronoi(f, SEEDS3[:2], mask=mask, backend="seq")
    w = gv.shape_functions(f, d, method="distance_ratio", backend="seq")
    rows = np.ravel_multi_index(np.nonzero(~mask), f.shape)
    assert w[rows].nnz == 0


# ---- bad input ------------------------------------------------------------------------------------

F2 = np.ones((4, 5), np.float32)

BAD_VORONOI = [
    (dict(field="abc", seeds=[[0, 0]]), TypeError, "real numeric"),
    (dict(field=np.ones((4, 5), bool), seeds=[[0, 0]]), TypeError, "real numeric"),
    (dict(field=np.ones((4, 5), complex), seeds=[[0, 0]]), TypeError, "real numeric"),
    (dict(field=np.ones(5), seeds=[[0]]), ValueError, "2D"),
    (dict(field=np.ones((2, 2, 2, 2)), seeds=[[0, 0, 0, 0]]), ValueError, "2D"),
    (dict(field=np.ones((0, 3)), seeds=[[0, 0]]), ValueError, "empty"),
    (dict(field=F2, seeds=[[0, 0, 0]]), ValueError, "(n, 2)"),
    (dict(field=F2, seeds=np.zeros((0, 2), int)), ValueError, "empty"),
    (dict(field=F2, seeds=[[0.5, 1.0]]), TypeError, "integer"),
    (dict(field=F2, seeds=[["a", "b"]]), TypeError, "numeric"),
    (dict(field=F2, seeds=[[4, 0]]), ValueError, "outside"),
    (dict(field=F2, seeds=[[0, -1]]), ValueError, "outside"),
    (dict(field=F2, seeds=[[1, 1], [1, 1]]), ValueError, "share the voxel (1, 1)"),
    (dict(field=np.where(np.arange(20).reshape(4, 5) == 7, 0, 1.0), seeds=[[1, 2]]), ValueError, "masked"),
    (dict(field=F2, seeds=[[0, 0]], world=True, spacing=2.0, origin=(10.0, 0.0)), ValueError, "outside"),
    (dict(field=F2, seeds=[[np.nan, 0.0]], world=True), ValueError, "non-finite"),
    (dict(field=F2, seeds=[[1e30, 0.0]], world=True), ValueError,
     "seed 0 at world point (1e+30, 0.0) lies outside the grid: its nearest voxel centre has index 1e+30 along array axis 0"),
    (dict(field=F2, seeds=[[0, 0]], spacing=(1.0,)), ValueError, "2 entries"),
    (dict(field=F2, seeds=[[0, 0]], spacing=(1.0, 0.0)), ValueError, "spacing"),
    (dict(field=F2, seeds=[[0, 0]], spacing=(1.0, np.inf)), ValueError, "spacing"),
    (dict(field=F2, seeds=[[0, 0]], spacing="x"), TypeError, "spacing"),
    (dict(field=F2, seeds=[[0, 0]], origin=(np.nan, 0)), ValueError, "origin"),
    (dict(field=F2, seeds=[[0, 0]], spacing=(1e-300, 1e-300)), ValueError, "length"),
    (dict(field=F2, seeds=[[0, 0]], orientation=np.eye(3)), ValueError, "(2, 2) matrix"),
    (dict(field=F2, seeds=[[0, 0]], orientation=[[1, 0], [0, np.nan]]), ValueError, "not finite"),
    (dict(field=F2, seeds=[[0, 0]], orientation=[[1, 0], [0, 2]]), ValueError, "not orthonormal"),
    (dict(field=F2, seeds=[[0, 0]], orientation=[["a", 0], [0, 1]]), TypeError, "orientation"),
    (dict(field=F2, seeds=[[0, 0]], metric="euclid"), ValueError, "unknown metric"),
    (dict(field=F2, seeds=[[0, 0]], metric=3), TypeError, "metric"),
    (dict(field=F2, seeds=[[0, 0]], connectivity=6), ValueError, "4 or 8"),
    (dict(field=np.ones((2, 2, 2)), seeds=[[0, 0, 0]], connectivity=8), ValueError, "6 or 18 or 26"),
    (dict(field=F2, seeds=[[0, 0]], connectivity=4.0), TypeError, "connectivity"),
    (dict(field=F2, seeds=[[0, 0]], backend="gpu"), ValueError, "unknown backend"),
    (dict(field=F2, seeds=[[0, 0]], backend="cuda"), ValueError, "not built"),
    (dict(field=F2, seeds=[[0, 0]], backend=None), TypeError, "backend"),
    (dict(field=F2, seeds=[[0, 0]], threads=0), ValueError, "threads"),
    (dict(field=F2, seeds=[[0, 0]], threads="2"), TypeError, "threads"),
    (dict(field=F2, seeds=[[0, 0]], backend="seq", threads=2), ValueError, "one thread"),
    (dict(field=F2, seeds=[[0, 0]], mask=np.ones((5, 4), bool)), ValueError, "mask has shape"),
    (dict(field=F2, seeds=[[0, 0]], mask=np.ones((4, 5), float)), TypeError, "boolean"),
    (dict(field=F2, seeds=[[0, 0]], progress=5), TypeError, "progress"),
    (dict(field=F2, seeds=[[0, 0]], mask=np.zeros((4, 5), bool)), ValueError, "masked"),
]


@pytest.mark.parametrize("kwargs,exc,text", BAD_VORONOI)
def test_bad_voronoi_input(kwargs, exc, text):
    kwargs = dict(kwargs)
    field, seeds = kwargs.pop("field"), kwargs.pop("seeds")
    with pytest.raises(exc) as e:
        gv.voronoi(field, seeds, **kwargs)
    assert text in str(e.value)


def test_bad_shape_function_input():
    f = field3()
    d = gv.voronoi(f, SEEDS3, backend="seq")
    cases = [
        (dict(method="natural"), ValueError, "unknown method"),
        (dict(method=1), TypeError, "method"),
        (dict(method="sibson", k=0), ValueError, "k must be"),
        (dict(method="sibson", k=2.5), TypeError, "k must be"),
        (dict(method="sibson", batch_size=0), ValueError, "batch_size"),
        (dict(method="sibson", metric="uniform"), ValueError, "differs"),
        (dict(method="sibson", connectivity=6), ValueError, "differs"),
        (dict(method="sibson", spacing=2.0), ValueError, "differs"),
        (dict(method="sibson", mask=np.ones(f.shape, bool)), ValueError, "mask"),
        (dict(method="sibson", points=[[9, 9, 9]]), ValueError, "outside"),
        (dict(method="sibson", progress="bar"), TypeError, "progress"),
    ]
    for kwargs, exc, text in cases:
        with pytest.raises(exc) as e:
            gv.shape_functions(f, d, **kwargs)
        assert text in str(e.value), kwargs
    with pytest.raises(ValueError, match="shape"):
        gv.shape_functions(np.ones((3, 3, 3), np.float32), d, method="sibson")
    with pytest.raises(ValueError, match="float32"):
        gv.shape_functions(f.astype(np.float64), d, method="sibson")


def test_bad_interpolate_input():
    w = gv.shape_functions(field3(), SEEDS3, method="distance_ratio", backend="seq")
    with pytest.raises(ValueError, match="3 node columns"):
        gv.interpolate(w, np.ones(2))
    with pytest.raises(TypeError, match="scipy.sparse"):
        gv.interpolate(np.ones((3, 3)), np.ones(3))
    with pytest.raises(TypeError, match="numeric"):
        gv.interpolate(w, np.array(["a", "b", "c"]))
    with pytest.raises(ValueError, match="outside"):
        gv.interpolate((np.array([[5]]), np.array([[1.0]])), np.ones(3))

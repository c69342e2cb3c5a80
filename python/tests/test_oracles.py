"""geovoronoi against scikit-image's MCP_Geometric and SciPy's csgraph.dijkstra on random small grids:
2D and 3D, every connectivity, anisotropic spacing, masks; and every backend against seq, bitwise."""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.csgraph
from conftest import CASES, offsets

import geovoronoi as gv

skimage_graph = pytest.importorskip("skimage.graph")

SHAPES = {2: (23, 19), 3: (9, 8, 7)}


def random_problem(rng, ndim, masked):
    shape = SHAPES[ndim]
    field = rng.uniform(0.5, 4.0, shape)
    spacing = tuple(rng.uniform(0.5, 2.0, ndim))
    mask = rng.random(shape) > 0.15 if masked else None
    free = np.argwhere(mask) if masked else np.argwhere(np.ones(shape, bool))
    seeds = free[rng.choice(len(free), 5, replace=False)]
    return field, spacing, mask, seeds


def labels_from_predecessors(pred_flat, seeds_flat, n):
    """Label of every voxel by following predecessors (-1: none) to a seed."""
    label = np.full(n, -1, np.int64)
    label[seeds_flat] = np.arange(len(seeds_flat))
    pred = pred_flat.copy()
    for _ in range(n):
        todo = (label < 0) & (pred >= 0)
        if not todo.any():
            break
        label[todo] = label[pred[todo]]
    return label


@pytest.mark.parametrize("ndim,conn", CASES)
@pytest.mark.parametrize("masked", [False, True])
def test_against_mcp_geometric(rng, ndim, conn, masked):
    field, spacing, mask, seeds = random_problem(rng, ndim, masked)
    d = gv.voronoi(field, seeds, spacing=spacing, metric="mean_cost", connectivity=conn, mask=mask, backend="seq")
    costs = field if mask is None else np.where(mask, field, np.inf)
    offs = offsets(ndim, conn)
    mcp = skimage_graph.MCP_Geometric(costs, offsets=offs, sampling=spacing)
    cum, trace = mcp.find_costs([tuple(s) for s in seeds])
    reached = np.isfinite(cum)
    assert np.array_equal(np.isfinite(d.distance), reached)
    np.testing.assert_allclose(d.distance[reached], cum[reached], rtol=1e-12, atol=0)
    # labels from MCP's traceback: the predecessor of voxel v is v - offsets[trace[v]]
    n = field.size
    flat_trace = trace.ravel()
    coords = np.indices(field.shape).reshape(ndim, -1).T
    pred = np.full(n, -1, np.int64)
    ok = (flat_trace >= 0) & reached.ravel()
    prev = coords[ok] - offs[flat_trace[ok]]
    pred[np.flatnonzero(ok)] = np.ravel_multi_index(tuple(prev.T), field.shape)
    seeds_flat = np.ravel_multi_index(tuple(seeds.T), field.shape)
    pred[seeds_flat] = -1
    label = labels_from_predecessors(pred, seeds_flat, n).reshape(field.shape)
    assert np.array_equal(d.label, np.where(reached, label, -1))


def stencil_graph(field, spacing, conn, metric):
    ndim = field.ndim
    n = field.size
    idx = np.arange(n).reshape(field.shape)
    rows, cols, vals = [], [], []
    for off in offsets(ndim, conn):
        src = tuple(slice(max(0, -o), field.shape[a] - max(0, o)) for a, o in enumerate(off))
        dst = tuple(slice(max(0, o), field.shape[a] - max(0, -o)) for a, o in enumerate(off))
        length = float(np.sqrt(np.sum((off * np.asarray(spacing)) ** 2)))
        bu, bv = field[src], field[dst]
        with np.errstate(divide="ignore"):  # masked voxels (0) are dropped below
            w = _weights(metric, length, bu, bv)
        inside = (bu > 0) & (bv > 0)
        rows.append(idx[src][inside])
        cols.append(idx[dst][inside])
        vals.append(w[inside])
    return scipy.sparse.csr_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def _weights(metric, length, bu, bv):
    if metric == "min_stiffness":
        return length / np.minimum(bu, bv)
    if metric == "mean_stiffness":
        return 2 * length / (bu + bv)
    return np.full(bu.shape, length)  # uniform


@pytest.mark.parametrize("ndim,conn", CASES)
@pytest.mark.parametrize("metric", ["min_stiffness", "mean_stiffness", "uniform"])
@pytest.mark.parametrize("masked", [False, True])
def test_against_csgraph_dijkstra(rng, ndim, conn, metric, masked):
    field, spacing, mask, seeds = random_problem(rng, ndim, masked)
    d = gv.voronoi(field, seeds, spacing=spacing, metric=metric, connectivity=conn, mask=mask, backend="seq")
    eff = field if mask is None else np.where(mask, field, 0.0)
    graph = stencil_graph(eff, spacing, conn, metric)
    seeds_flat = np.ravel_multi_index(tuple(seeds.T), field.shape)
    dist, pred, src = scipy.sparse.csgraph.dijkstra(graph, indices=seeds_flat, min_only=True,
                                                    return_predecessors=True)
    dist = dist.reshape(field.shape)
    reached = np.isfinite(dist)
    assert np.array_equal(np.isfinite(d.distance), reached)
    np.testing.assert_allclose(d.distance[reached], dist[reached], rtol=1e-12, atol=0)
    # Labels: where one seed is clearly nearest it must be ours; at (near-)ties (the uniform metric
    # has exact ones) csgraph's choice is arbitrary, so ours must be one of the tied seeds.
    per_seed = scipy.sparse.csgraph.dijkstra(graph, indices=seeds_flat).reshape((len(seeds),) + field.shape)
    tied = per_seed <= dist * (1 + 1e-9)
    lab = d.label
    assert np.all(lab[~reached] == -1)
    ours_is_tied = np.take_along_axis(tied, np.maximum(lab, 0)[np.newaxis], axis=0)[0]
    assert np.all(ours_is_tied[reached])
    clear = reached & (tied.sum(axis=0) == 1)
    seed_index = {int(v): i for i, v in enumerate(seeds_flat)}
    label = np.array([seed_index[int(s)] if s >= 0 else -1 for s in src]).reshape(field.shape)
    assert clear.sum() > field.size // 2
    assert np.array_equal(lab[clear], label[clear])


@pytest.mark.parametrize("ndim,conn", CASES)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_backends_bitwise_equal(rng, ndim, conn, dtype):
    if "thrust" not in gv.backends():
        pytest.skip("the thrust backend is not built into this package")
    field, spacing, mask, seeds = random_problem(rng, ndim, True)
    field = field.astype(dtype)
    a = gv.voronoi(field, seeds, spacing=spacing, connectivity=conn, mask=mask, backend="seq", parent=True)
    b = gv.voronoi(field, seeds, spacing=spacing, connectivity=conn, mask=mask, backend="thrust", threads=2,
                   parent=True)
    assert a.distance.dtype == dtype
    assert np.array_equal(a.distance.view(np.uint8), b.distance.view(np.uint8))
    assert np.array_equal(a.label, b.label)
    assert np.array_equal(a.parent, b.parent)

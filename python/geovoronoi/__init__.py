"""Geodesic Voronoi diagrams and Voronoi shape functions on voxel grids.

NumPy in, NumPy and SciPy out. Arrays use NumPy's axis order: ``[z, y, x]`` in 3D, ``[y, x]`` in
2D; ``spacing`` and ``origin`` are given in the same order (like scikit-image's ``sampling``), and
seeds are ``(n, ndim)`` arrays of array indices (or world points with ``world=True``).

>>> import numpy as np, geovoronoi as gv
>>> stiffness = np.ones((32, 48, 64), np.float32)
>>> d = gv.voronoi(stiffness, [[4, 4, 4], [20, 30, 50]], spacing=(2.0, 1.0, 1.0))
>>> d.label[4, 4, 5], d.distance.dtype
(0, dtype('float32'))
>>> w = gv.shape_functions(stiffness, d, method="distance_ratio", k=2)   # scipy.sparse.csr_array
>>> u = gv.interpolate(w, np.array([0.0, 1.0]), shape=stiffness.shape)

See docs/python.md for the full description.
"""

from __future__ import annotations

import math
import numbers
import os
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _geovoronoi as _ext

__all__ = [
    "Diagram",
    "METRICS",
    "METHODS",
    "backends",
    "default_backend",
    "interpolate",
    "read_image",
    "shape_functions",
    "voronoi",
    "write_image",
    "write_vti",
]
__version__ = "0.1.0"

#: Edge-weight rules (see docs/policies.md): ``uniform`` (plain length), ``min_stiffness`` (SOFA's,
#: length / min(b_u, b_v)), ``mean_stiffness`` (2 length / (b_u + b_v)) and ``mean_cost``
#: (length (c_u + c_v) / 2, scikit-image's ``MCP_Geometric``).
METRICS = ("uniform", "min_stiffness", "mean_stiffness", "mean_cost")
#: Shape-function methods.
METHODS = ("distance_ratio", "sibson", "laplace")

_DEFAULT_CONNECTIVITY = {2: 8, 3: 26}


def backends() -> list:
    """The backends built into this package (``"seq"`` always, ``"thrust"`` when built with
    Thrust and OpenMP). CUDA is not built into the Python package."""
    return list(_ext._backends())


def default_backend() -> str:
    """The backend that ``backend="auto"`` picks here: ``"thrust"`` when it is built and the
    machine has more than one hardware thread, else ``"seq"``."""
    return _ext._resolve_backend("auto")


class Diagram:
    """A geodesic Voronoi diagram returned by :func:`voronoi`.

    Attributes
    ----------
    distance : ndarray
        Geodesic distance of every voxel to its nearest seed, the field's dtype (float32 or
        float64); ``+inf`` where masked or unreachable.
    label : ndarray of int32
        Index of that seed in ``seeds`` (ties go to the lowest index); ``-1`` where masked or
        unreachable.
    parent : ndarray of int64 or None
        With ``parent=True``: for every reached voxel that is not a seed, the flat (C-order) index
        of its predecessor on a shortest path (the lowest such neighbour); ``-1`` elsewhere.
    seeds : ndarray of int64, shape (n, ndim)
        The seeds as array indices (world points rounded to the nearest voxel with ``world=True``).
    spacing, origin : tuple of float
        The grid's voxel size and the world position of voxel 0, in array-axis order.
    orientation : ndarray, shape (ndim, ndim)
        The grid's direction matrix in array-axis order (rows: world axes, columns: array axes), as
        :func:`read_image` returns it; the identity unless ``voronoi`` was given one.
    metric : str
    connectivity : int

    The arrays are views of the library's own result memory (no copy was made); they stay valid
    as long as any of them is referenced.
    """

    __slots__ = ("distance", "label", "parent", "seeds", "spacing", "origin", "orientation", "metric",
                 "connectivity", "_handle", "_mask")

    def __init__(self, handle, distance, label, parent, seeds, spacing, origin, metric, connectivity, mask,
                 orientation=None):
        self._handle = handle
        self.distance = distance
        self.label = label
        self.parent = parent
        self.seeds = seeds
        self.spacing = spacing
        self.origin = origin
        self.orientation = np.eye(len(spacing)) if orientation is None else orientation
        self.metric = metric
        self.connectivity = connectivity
        self._mask = mask

    @property
    def shape(self) -> Tuple[int, ...]:
        """The grid's shape (that of the field)."""
        return self.distance.shape

    def __repr__(self) -> str:
        return (f"Diagram(shape={self.distance.shape}, seeds={len(self.seeds)}, dtype={self.distance.dtype}, "
                f"metric={self.metric!r}, connectivity={self.connectivity})")


# ---- argument normalisation ----------------------------------------------------------------------


def _field_array(field: Any) -> np.ndarray:
    """float32/float64 C-contiguous native-order array, the input itself whenever it is one."""
    a = np.asarray(field)
    if a.dtype.kind == "b" or a.dtype.kind not in "iuf":
        raise TypeError(f"geovoronoi: the field must be a real numeric array (float32 or float64), got dtype {a.dtype}")
    if a.ndim not in (2, 3):
        raise ValueError(f"geovoronoi: the field must be a 2D [y, x] or 3D [z, y, x] array, got shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"geovoronoi: the field is empty (shape {a.shape})")
    if a.dtype == np.float32 or a.dtype == np.float64:
        if not a.dtype.isnative:
            a = a.astype(a.dtype.newbyteorder("="))
    else:
        a = a.astype(np.float64)  # integers, float16, long double: float64 (a copy)
    if not a.flags.c_contiguous:
        a = np.ascontiguousarray(a)  # a copy: the library needs x fastest, contiguous
    return a


def _apply_mask(field: np.ndarray, mask: Any) -> np.ndarray:
    m = np.asarray(mask)
    if m.dtype.kind not in "biu":
        raise TypeError(f"geovoronoi: the mask must be a boolean array, got dtype {m.dtype}")
    if m.shape != field.shape:
        raise ValueError(f"geovoronoi: the mask has shape {m.shape} but the field has shape {field.shape}")
    # Outside voxels get NaN, which every metric treats as outside the domain (a masked copy).
    return np.where(m.astype(bool), field, field.dtype.type(np.nan))


def _axis_tuple(value: Any, ndim: int, name: str, default: float) -> Tuple[float, ...]:
    if value is None:
        return (default,) * ndim
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return (float(value),) * ndim
    try:
        t = tuple(float(v) for v in np.asarray(value, dtype=np.float64).ravel())
    except (TypeError, ValueError):
        raise TypeError(f"geovoronoi: {name} must be a number or a sequence of {ndim} numbers, got {value!r}") from None
    if np.asarray(value).ndim != 1 or len(t) != ndim:
        raise ValueError(f"geovoronoi: {name} must have {ndim} entries (array-axis order), got {value!r}")
    return t


def _check_spacing(spacing: Tuple[float, ...]) -> None:
    for i, s in enumerate(spacing):
        if not (math.isfinite(s) and s > 0):
            raise ValueError(f"geovoronoi: spacing[{i}] is {s}; spacing must be finite and > 0")


def _check_origin(origin: Tuple[float, ...]) -> None:
    for i, o in enumerate(origin):
        if not math.isfinite(o):
            raise ValueError(f"geovoronoi: origin[{i}] is {o}; the origin must be finite")


def _orientation(orientation: Any, ndim: int) -> np.ndarray:
    """The (ndim, ndim) direction matrix in array-axis order (identity when None), checked like the
    library's grids: finite, and orthonormal within 1e-6 (so world-to-index uses the transpose)."""
    if orientation is None:
        return np.eye(ndim)
    d = np.asarray(orientation)
    if d.dtype == object or d.dtype.kind not in "biuf":
        raise TypeError(f"geovoronoi: orientation must be a numeric ({ndim}, {ndim}) matrix, got dtype {d.dtype}")
    d = d.astype(np.float64)
    if d.shape != (ndim, ndim):
        raise ValueError(f"geovoronoi: orientation must be a ({ndim}, {ndim}) matrix, got shape {d.shape}")
    if not np.all(np.isfinite(d)):
        raise ValueError(f"geovoronoi: the orientation {d.tolist()} has an entry that is not finite")
    worst = float(np.max(np.abs(d.T @ d - np.eye(ndim))))
    if not worst <= 1e-6:
        raise ValueError(f"geovoronoi: the orientation {d.tolist()} is not orthonormal (largest entry of "
                         f"D^T D - I is {worst:g}, tolerance 1e-06)")
    return d


def _metric(metric: Any) -> str:
    if not isinstance(metric, str):
        raise TypeError(f"geovoronoi: metric must be a string ({', '.join(METRICS)}), got {metric!r}")
    if metric not in METRICS:
        raise ValueError(f"geovoronoi: unknown metric {metric!r} ({', '.join(METRICS)})")
    return metric


def _connectivity(connectivity: Any, ndim: int) -> int:
    if connectivity is None:
        return _DEFAULT_CONNECTIVITY[ndim]
    if isinstance(connectivity, bool) or not isinstance(connectivity, numbers.Integral):
        raise TypeError(f"geovoronoi: connectivity must be an integer, got {connectivity!r}")
    allowed = (4, 8) if ndim == 2 else (6, 18, 26)
    if int(connectivity) not in allowed:
        raise ValueError(f"geovoronoi: connectivity of a {ndim}D field must be "
                         f"{' or '.join(map(str, allowed))}, got {connectivity}")
    return int(connectivity)


def _backend(backend: Any) -> str:
    if not isinstance(backend, str):
        raise TypeError(f"geovoronoi: backend must be a string (auto, seq or thrust), got {backend!r}")
    return backend


def _threads(threads: Any) -> int:
    if threads is None:
        return 0
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"geovoronoi: threads must be a positive integer or None, got {threads!r}")
    if threads < 1:
        raise ValueError(f"geovoronoi: threads must be >= 1, got {threads}")
    return int(threads)


def _progress(progress: Any) -> Any:
    if progress is not None and not callable(progress):
        raise TypeError(f"geovoronoi: progress must be a callable or None, got {progress!r}")
    return progress


def _inside(values: np.ndarray, metric: str) -> np.ndarray:
    if metric == "mean_cost":
        return np.isfinite(values) & (values >= 0)
    return values > 0  # NaN compares false


def _points(points: Any, ndim: int, world: bool, spacing, origin, shape, what: str,
            orientation: Optional[np.ndarray] = None) -> np.ndarray:
    """(n, ndim) int64 array indices of seeds or query points, bounds-checked."""
    p = np.asarray(points)
    if p.dtype == object or p.dtype.kind not in "biuf":
        raise TypeError(f"geovoronoi: {what} must be a numeric (n, {ndim}) array, got dtype {p.dtype}")
    if p.ndim == 1 and p.shape[0] == ndim:
        p = p.reshape(1, ndim)
    if p.ndim != 2 or p.shape[1] != ndim:
        raise ValueError(f"geovoronoi: {what} must be an (n, {ndim}) array of "
                         f"{'world points' if world else 'array indices'}, got shape {p.shape}")
    if p.shape[0] == 0:
        raise ValueError(f"geovoronoi: the {what} list is empty")
    if world:
        x = p.astype(np.float64)
        if not np.all(np.isfinite(x)):
            raise ValueError(f"geovoronoi: {what} contain a non-finite world coordinate")
        # nearest voxel centre, the library's rule (grid::nearest_voxel): per index axis a,
        # floor((D^T (x - origin))_a / spacing_a + 0.5), summed in the library's axis order (x first)
        # and skipping zero entries, so the rounding is the C++ tool's bit for bit
        d = np.eye(ndim) if orientation is None else orientation
        rel = x - np.asarray(origin)
        u = np.zeros_like(x)
        for a in range(ndim):
            for r in reversed(range(ndim)):
                if d[r, a] != 0.0:
                    u[:, a] = u[:, a] + d[r, a] * rel[:, r]
        idx = np.floor(u / np.asarray(spacing) + 0.5)
        bad = ~np.all((idx >= 0) & (idx < np.asarray(shape)), axis=1)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"geovoronoi: {what[:-1]} {i} at world point {tuple(x[i])} lies outside the grid "
                             f"(nearest voxel {tuple(int(v) for v in idx[i])}, shape {tuple(shape)})")
        return np.ascontiguousarray(idx, dtype=np.int64)
    if p.dtype.kind in "fb":
        raise TypeError(f"geovoronoi: {what} must be integer array indices, got dtype {p.dtype} "
                        "(pass world=True for physical coordinates)")
    if p.dtype.kind == "u" and p.size and p.max() > np.iinfo(np.int64).max:
        raise ValueError(f"geovoronoi: {what} hold an index beyond int64")
    idx = p.astype(np.int64)
    bad = ~np.all((idx >= 0) & (idx < np.asarray(shape)), axis=1)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"geovoronoi: {what[:-1]} {i} at {tuple(int(v) for v in idx[i])} lies outside the "
                         f"array of shape {tuple(shape)}")
    return np.ascontiguousarray(idx)


def _check_seeds(field: np.ndarray, seeds: np.ndarray, metric: str) -> None:
    """Masked and duplicate seeds, named in array-axis order (the library checks them again)."""
    values = field[tuple(seeds.T)]
    bad = ~_inside(values, metric)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"geovoronoi: seed {i} at {tuple(int(v) for v in seeds[i])} lies on a masked voxel "
                         f"(field value {values[i]})")
    flat = np.ravel_multi_index(tuple(seeds.T), field.shape)
    order = np.argsort(flat, kind="stable")
    dup = np.flatnonzero(flat[order][1:] == flat[order][:-1])
    if dup.size:
        a, b = int(order[dup[0]]), int(order[dup[0] + 1])
        raise ValueError(f"geovoronoi: seeds {a} and {b} share the voxel {tuple(int(v) for v in seeds[a])}")


# ---- solvers ---------------------------------------------------------------------------------------


def voronoi(field: Any, seeds: Any, *, spacing: Any = None, origin: Any = None, orientation: Any = None,
            metric: str = "min_stiffness",
            connectivity: Optional[int] = None, mask: Any = None, world: bool = False, backend: str = "auto",
            threads: Optional[int] = None, progress: Optional[Callable[[float], Any]] = None,
            parent: bool = False) -> Diagram:
    """Geodesic Voronoi diagram of ``seeds`` on the grid of ``field``.

    Every voxel gets its geodesic distance to the nearest seed (shortest path on the voxel grid,
    each edge weighted by the metric from the field values of the two voxels it joins) and the
    index of that seed; ties go to the lowest index. Every backend returns bitwise the same result.

    Parameters
    ----------
    field : array_like, 2D ``[y, x]`` or 3D ``[z, y, x]``
        Stiffness (``*_stiffness``, ``uniform``: voxels with value <= 0 or NaN are outside the
        domain) or cost (``mean_cost``: outside where < 0, NaN or inf). float32 and float64 arrays
        are used as given (C-contiguous ones without a copy); other real dtypes become float64.
    seeds : array_like, shape (n, ndim)
        Integer array indices of the seeds (label i = row i), or world points with ``world=True``.
    spacing : float or sequence, optional
        Physical voxel size per array axis (default 1).
    origin : sequence, optional
        World position of voxel 0's centre, per array axis (default 0).
    orientation : array_like, shape (ndim, ndim), optional
        Direction matrix in array-axis order, as :func:`read_image` returns it (default identity):
        world = origin + orientation @ (index * spacing). Only world seeds (``world=True``) and the
        outputs' geometry depend on it; it must be orthonormal within 1e-6.
    metric : {"min_stiffness", "mean_stiffness", "mean_cost", "uniform"}
    connectivity : int, optional
        4 or 8 in 2D, 6, 18 or 26 in 3D; default the largest.
    mask : array_like of bool, optional
        Voxels where it is False are outside the domain (the field is then copied once).
    world : bool
        Seeds are world points, each rounded to the nearest voxel centre.
    backend : {"auto", "seq", "thrust"}
        ``seq``: sequential Dijkstra; ``thrust``: Thrust on OpenMP threads (when built).
    threads : int, optional
        OpenMP threads for ``thrust`` (default: OpenMP's default); ``seq`` accepts only 1.
    progress : callable, optional
        Called with increments of the percentage done (they add up to 100), e.g.
        ``tqdm(total=100).update``, from the solver's progress hook (solve_options::progress); an
        exception it raises cancels the solve and propagates.
    parent : bool
        Also compute the parent (predecessor) image.

    Returns
    -------
    Diagram

    Raises
    ------
    ValueError
        Bad shapes, spacing, connectivity, metric, backend; seeds outside the grid, on a masked
        voxel, or sharing a voxel (the message names the seed, in array-axis order).
    TypeError
        Non-numeric field, seeds or mask, non-integer seeds without ``world=True``.

    Notes
    -----
    The GIL is released during the solve: other Python threads run meanwhile, and several solves
    may run in parallel threads. Ctrl-C during a solve cancels it (KeyboardInterrupt).
    """
    f = _field_array(field)
    ndim = f.ndim
    sp = _axis_tuple(spacing, ndim, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, ndim, "origin", 0.0)
    _check_origin(org)
    orient = _orientation(orientation, ndim)
    m = _metric(metric)
    conn = _connectivity(connectivity, ndim)
    b = _backend(backend)
    nthreads = _threads(threads)
    cb = _progress(progress)
    mask_array = None
    if mask is not None:
        f = _apply_mask(f, mask)
        mask_array = np.asarray(mask)
    s = _points(seeds, ndim, bool(world), sp, org, f.shape, "seeds", orient)
    _check_seeds(f, s, m)
    handle, distance, label, par, seed_idx = _ext._voronoi(f, list(sp), list(org), m, conn, b, nthreads, s, False,
                                                           bool(parent), cb)
    return Diagram(handle, distance, label, par, seed_idx, sp, org, m, conn, mask_array, orient)


def shape_functions(field: Any, seeds_or_diagram: Any, *, method: str, k: int = 4, points: Any = None,
                    world: bool = False, spacing: Any = None, origin: Any = None, orientation: Any = None,
                    metric: Optional[str] = None, connectivity: Optional[int] = None, mask: Any = None,
                    backend: str = "auto", threads: Optional[int] = None,
                    progress: Optional[Callable[[float], Any]] = None, fixed_k: bool = False,
                    batch_size: int = 4096):
    """Voronoi shape functions of the nodes (the seeds) at every voxel, or at ``points``.

    Parameters
    ----------
    field : array_like
        The field, as for :func:`voronoi` (with a diagram: the field it was computed on).
    seeds_or_diagram : array_like or Diagram
        The nodes: seeds as for :func:`voronoi` (the diagram is computed first, with the same
        options), or a :class:`Diagram` (then ``spacing``, ``origin``, ``orientation``, ``metric``,
        ``connectivity`` and ``mask`` default to, and must equal, the diagram's).
    method : {"distance_ratio", "sibson", "laplace"}
        Distance Ratio (SOFA's default), Sibson (natural-neighbour) or Laplace (non-Sibsonian); see
        docs/shape-functions.md.
    k : int
        Most nodes kept per voxel (SOFA's nbRef); the smallest weights are dropped and the rest
        renormalised.
    points : array_like, shape (m, ndim), optional
        Only these voxels (array indices, or world points with ``world=True``, rounded to the
        nearest voxel centre through ``orientation``): row i of the result is point i. Only those
        rows are computed (the library's ``shape_functions_at``), bitwise equal to the same rows of
        the full computation.
    metric : str, optional
        Default ``"min_stiffness"`` (with seeds) or the diagram's.
    fixed_k : bool
        Also return SOFA's fixed-K layout: ``(indices, weights)`` arrays of shape ``shape + (k,)``
        (or ``(m, k)`` with ``points``); slots sorted by decreasing weight, empty ones have index
        -1 and weight 0.
    batch_size : int
        Queries per backend call (Sibson, Laplace).
    progress : callable, optional
        Called with increments of the percentage done (they add up to 100); a tqdm bar's
        ``update`` works with ``total=100``. An exception it raises cancels the computation and
        propagates. Ctrl-C cancels too (KeyboardInterrupt).

    Other parameters are those of :func:`voronoi`.

    Returns
    -------
    scipy.sparse.csr_array, shape (voxels or points, nodes)
        Rows in C order of the field's voxels (``np.ravel_multi_index``), weights in the field's
        dtype; rows sum to 1 inside the domain, empty outside. With ``fixed_k=True``:
        ``(csr, indices, weights)``.
    """
    import scipy.sparse

    if not isinstance(method, str):
        raise TypeError(f"geovoronoi: method must be a string ({', '.join(METHODS)}), got {method!r}")
    if method not in METHODS:
        raise ValueError(f"geovoronoi: unknown method {method!r} ({', '.join(METHODS)})")
    if isinstance(k, bool) or not isinstance(k, numbers.Integral):
        raise TypeError(f"geovoronoi: k must be an integer, got {k!r}")
    if k < 1:
        raise ValueError(f"geovoronoi: k must be >= 1, got {k}")
    if isinstance(batch_size, bool) or not isinstance(batch_size, numbers.Integral):
        raise TypeError(f"geovoronoi: batch_size must be an integer, got {batch_size!r}")
    if batch_size < 1:
        raise ValueError(f"geovoronoi: batch_size must be >= 1, got {batch_size}")
    cb = _progress(progress)
    f = _field_array(field)
    ndim = f.ndim
    if isinstance(seeds_or_diagram, Diagram):
        d = seeds_or_diagram
        if d.shape != f.shape:
            raise ValueError(f"geovoronoi: the diagram has shape {d.shape} but the field has shape {f.shape}")
        if (f.dtype != d.distance.dtype):
            raise ValueError(f"geovoronoi: the diagram was computed on a {d.distance.dtype} field, this one is {f.dtype}")
        for name, given, own in (("spacing", spacing, d.spacing), ("origin", origin, d.origin)):
            if given is not None and _axis_tuple(given, ndim, name, 0.0) != own:
                raise ValueError(f"geovoronoi: {name} differs from the diagram's {own}")
        if orientation is not None and not np.array_equal(_orientation(orientation, ndim), d.orientation):
            raise ValueError(f"geovoronoi: orientation differs from the diagram's {d.orientation.tolist()}")
        if metric is not None and _metric(metric) != d.metric:
            raise ValueError(f"geovoronoi: metric {metric!r} differs from the diagram's {d.metric!r}")
        if connectivity is not None and _connectivity(connectivity, ndim) != d.connectivity:
            raise ValueError(f"geovoronoi: connectivity {connectivity} differs from the diagram's {d.connectivity}")
        if mask is not None:
            raise ValueError("geovoronoi: pass the mask to voronoi(); a diagram carries its mask")
        if d._mask is not None:
            f = _apply_mask(f, d._mask)
    else:
        d = voronoi(f, seeds_or_diagram, spacing=spacing, origin=origin, orientation=orientation,
                    metric="min_stiffness" if metric is None else metric, connectivity=connectivity, mask=mask,
                    world=world, backend=backend, threads=threads)
        if d._mask is not None:
            f = _apply_mask(f, d._mask)
    qp = None
    if points is not None:
        qp = _points(points, ndim, bool(world), d.spacing, d.origin, f.shape, "points", d.orientation)
    data, indices, indptr, nodes, fixed_idx, fixed_w = _ext._shape_functions(
        f, list(d.spacing), list(d.origin), d.metric, d.connectivity, _backend(backend), _threads(threads),
        d._handle, method, int(k), int(batch_size), cb, None if qp is None else np.ascontiguousarray(qp, np.int64))
    # with points, only those voxels are computed (the library's shape_functions_at): one row each
    w = scipy.sparse.csr_array((data, indices, indptr), shape=(f.size if qp is None else len(qp), int(nodes)))
    if fixed_k:
        return w, fixed_idx, fixed_w
    return w


def interpolate(weights: Any, nodal_values: Any, *, shape: Optional[Sequence[int]] = None) -> np.ndarray:
    """Values at the voxels (or points) interpolated from values at the nodes.

    Parameters
    ----------
    weights : scipy.sparse array or matrix (rows x nodes), or the ``(indices, weights)`` pair of
        the fixed-K layout.
    nodal_values : array_like, shape (nodes,) or (nodes, c)
    shape : sequence of int, optional
        Reshape the rows to this grid shape (sparse weights only; the fixed-K layout keeps its own).

    Returns
    -------
    ndarray: row i = sum over nodes j of weights[i, j] * nodal_values[j]; 0 where a row is empty.
    """
    values = np.asarray(nodal_values)
    if values.dtype.kind not in "iufc":
        raise TypeError(f"geovoronoi: nodal_values must be numeric, got dtype {values.dtype}")
    if values.ndim not in (1, 2):
        raise ValueError(f"geovoronoi: nodal_values must be (nodes,) or (nodes, c), got shape {values.shape}")
    if isinstance(weights, tuple):
        if len(weights) != 2:
            raise ValueError("geovoronoi: fixed-K weights are an (indices, weights) pair")
        idx, w = (np.asarray(a) for a in weights)
        if idx.shape != w.shape:
            raise ValueError(f"geovoronoi: indices {idx.shape} and weights {w.shape} differ in shape")
        if idx.size and (idx.max() >= values.shape[0] or idx.min() < -1):
            raise ValueError(f"geovoronoi: an index is outside the {values.shape[0]} nodal values")
        gathered = values[np.maximum(idx, 0)]
        ww = np.where(idx >= 0, w, 0)
        if values.ndim == 2:
            return np.einsum("...k,...kc->...c", ww, gathered)
        return np.einsum("...k,...k->...", ww, gathered)
    import scipy.sparse

    if not scipy.sparse.issparse(weights):
        raise TypeError(f"geovoronoi: weights must be a scipy.sparse array or an (indices, weights) pair, "
                        f"got {type(weights).__name__}")
    if weights.shape[1] != values.shape[0]:
        raise ValueError(f"geovoronoi: weights have {weights.shape[1]} node columns but {values.shape[0]} "
                         "nodal values were given")
    out = np.asarray(weights @ values)
    if shape is not None:
        out = out.reshape(tuple(shape) + values.shape[1:])
    return out


# ---- images -----------------------------------------------------------------------------------------


def read_image(path: Union[str, os.PathLike]) -> Tuple[np.ndarray, Tuple[float, ...], Tuple[float, ...], np.ndarray]:
    """Read a MetaImage file (``.mhd`` + raw, or ``.mha``).

    Returns
    -------
    (array, spacing, origin, orientation)
        ``array`` in the file's element type, axes ``[z, y, x]`` (``[y, x]`` for 2D files), with a
        trailing channel axis when the file has several channels (ITK's interleaved layout);
        ``spacing`` and ``origin`` in array-axis order; ``orientation`` the direction cosines as an
        (ndim, ndim) matrix with rows and columns in array-axis order.

    Raises
    ------
    OSError
        Missing, unreadable or malformed file (the message names the file and the problem).
    """
    arr, spacing, origin, orientation = _ext._read_image(os.fspath(path))
    return arr, tuple(spacing), tuple(origin), orientation


def _image_array(array: Any, what: str) -> np.ndarray:
    a = np.asarray(array)
    if a.dtype == np.bool_:
        a = a.astype(np.uint8)
    if a.dtype.kind not in "iuf" or a.dtype.itemsize > 8 or a.dtype == np.float16:
        raise TypeError(f"geovoronoi: {what}: unsupported dtype {a.dtype} ((u)int8..64, float32, float64)")
    if not a.dtype.isnative:
        a = a.astype(a.dtype.newbyteorder("="))
    return np.ascontiguousarray(a)


def write_image(path: Union[str, os.PathLike], array: Any, spacing: Any = None, origin: Any = None,
                orientation: Any = None, *, channels: bool = False, planar: bool = False,
                compress: bool = False) -> None:
    """Write an array as MetaImage: ``.mha`` (one file) or ``.mhd`` + ``.raw``.

    ``array`` has axes ``[z, y, x]`` or ``[y, x]`` (plus a trailing channel axis with
    ``channels=True``); spacing, origin and orientation as :func:`read_image` returns them. The
    element type is the array's. ``planar=True`` stores several channels one volume after another
    (SOFA's layout) instead of interleaved (ITK's); ``compress=True`` needs zlib.
    """
    a = _image_array(array, "write_image")
    nd = a.ndim - (1 if channels else 0)
    if nd not in (1, 2, 3):
        raise ValueError(f"geovoronoi: write_image needs a 1D, 2D or 3D array (plus a channel axis), got {a.shape}")
    sp = _axis_tuple(spacing, nd, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, nd, "origin", 0.0)
    _check_origin(org)
    if orientation is None:
        orient = np.eye(nd)
    else:
        orient = np.asarray(orientation, dtype=np.float64)
        if orient.shape != (nd, nd):
            raise ValueError(f"geovoronoi: orientation must be a ({nd}, {nd}) matrix, got shape {orient.shape}")
    nch = a.shape[-1] if channels else 1
    if channels and nch < 1:
        raise ValueError("geovoronoi: the channel axis is empty")
    _ext._write_image(os.fspath(path), a, int(nch), list(sp), list(org), [float(x) for x in orient.ravel()],
                      bool(planar), bool(compress))


def write_vti(path: Union[str, os.PathLike], arrays: Mapping[str, Any], spacing: Any = None, origin: Any = None,
              orientation: Any = None, *, ndim: Optional[int] = None) -> None:
    """Write arrays on one grid as a VTK XML ImageData file (``.vti``, ParaView).

    ``arrays`` maps names to arrays of the grid's shape (``[z, y, x]`` or ``[y, x]``), optionally
    with a trailing component axis; the first is the active scalar. The grid's dimension is that of
    the first array unless ``ndim`` says otherwise. ``orientation`` (array-axis order, as
    :func:`read_image` returns it) becomes the file's ``Direction``. A :class:`Diagram` can be written with
    ``{"label": d.label, "distance": d.distance}``.
    """
    if not arrays:
        raise ValueError("geovoronoi: write_vti needs at least one array")
    items = [(str(name), _image_array(a, f"write_vti array {name!r}")) for name, a in arrays.items()]
    nd = items[0][1].ndim if ndim is None else int(ndim)
    if nd not in (2, 3):
        raise ValueError(f"geovoronoi: write_vti writes 2D or 3D grids, got {nd} dimensions")
    shape = items[0][1].shape[:nd]
    for name, a in items:
        if a.shape[:nd] != shape or a.ndim not in (nd, nd + 1):
            raise ValueError(f"geovoronoi: write_vti: array {name!r} has shape {a.shape}, the grid is {shape}")
    sp = _axis_tuple(spacing, nd, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, nd, "origin", 0.0)
    _check_origin(org)
    orient = _orientation(orientation, nd)
    _ext._write_vti(os.fspath(path), items, list(shape), list(sp), list(org), [float(x) for x in orient.ravel()])

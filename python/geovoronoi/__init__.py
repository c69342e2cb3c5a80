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
import weakref
from typing import Any, Callable, Dict, Mapping, NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _geovoronoi as _ext

__all__ = [
    "BranchingDiagram",
    "BranchingGrid",
    "BranchingWeights",
    "Cut",
    "Diagram",
    "Voxelization",
    "ShapeState",
    "cut_from_mesh",
    "cut_from_polylines",
    "read_mesh",
    "update",
    "update_shape_functions",
    "METRICS",
    "METHODS",
    "REDUCTIONS",
    "backends",
    "branching_grid",
    "default_backend",
    "interpolate",
    "read_image",
    "shape_functions",
    "voronoi",
    "voxelize",
    "write_image",
    "write_vti",
]
__version__ = "0.1.0"

#: Edge-weight rules (see docs/policies.md): ``uniform`` (plain length), ``min_stiffness`` (SOFA's,
#: length / min(b_u, b_v)), ``mean_stiffness`` (2 length / (b_u + b_v)) and ``mean_cost``
#: (length (c_u + c_v) / 2, scikit-image's ``MCP_Geometric``).
METRICS = ("uniform", "min_stiffness", "mean_stiffness", "mean_cost")
#: Stiffness reductions of a branching grid's copies (:func:`branching_grid`).
REDUCTIONS = ("mean", "min", "max", "harmonic")
#: Shape-function methods.
METHODS = ("distance_ratio", "sibson", "laplace")

_DEFAULT_CONNECTIVITY = {2: 8, 3: 26}


def backends() -> list:
    """The backends built into this package (``"seq"`` always, ``"thrust"`` when built with
    Thrust and OpenMP). CUDA is not built into the Python package."""
    return list(_ext._backends())


def default_backend() -> str:
    """The backend that ``backend="auto"`` picks here for a large problem (a smaller one runs on
    ``"seq"``; see :func:`voronoi`): ``"thrust"`` when it is built and the
    machine has more than one hardware thread, else ``"seq"``."""
    return _ext._default_backend()


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
    cut : Cut or None
        Every cut edge the diagram was solved with (``voronoi(..., cut=)``, accumulated over
        :func:`update` calls); None without cuts.
    stats : dict or None
        For a diagram returned by :func:`update`: what the update did (voxels invalidated, settled,
        reparented, ...; the library's ``update_stats``); None for a full solve.

    The arrays are views of the library's own result memory (no copy was made); they stay valid
    as long as any of them is referenced.
    """

    __slots__ = ("distance", "label", "parent", "seeds", "spacing", "origin", "orientation", "metric",
                 "connectivity", "cut", "stats", "_handle", "_mask", "_change", "__weakref__")

    def __init__(self, handle, distance, label, parent, seeds, spacing, origin, metric, connectivity, mask,
                 orientation=None, cut=None):
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
        self.cut = cut
        self.stats = None
        self._change = None  # (weakref to the diagram before, normalised change) after update()

    @property
    def shape(self) -> Tuple[int, ...]:
        """The grid's shape (that of the field)."""
        return self.distance.shape

    def __repr__(self) -> str:
        return (f"Diagram(shape={self.distance.shape}, seeds={len(self.seeds)}, dtype={self.distance.dtype}, "
                f"metric={self.metric!r}, connectivity={self.connectivity}"
                f"{'' if self.cut is None else f', cut edges={len(self.cut)}'})")


class ShapeState:
    """Distance Ratio's per-node searches, kept with the weights of one diagram so that
    :func:`update_shape_functions` repairs them around a change instead of running them again
    (the library's ``shape_options::keep_update_state``).

    Returned by ``shape_functions(diagram, method="distance_ratio", keep_state=True)`` and by
    ``update_shape_functions(..., state=...)``, which gives the state of the weights it returns. A state
    belongs to the diagram it was computed on: it is accepted only with that diagram as
    ``diagram_before``. It is immutable (an update returns a new one; they share what did not change)
    and holds ``nbytes`` bytes: 12 (float) or 16 (double) per voxel of each node's support and frontier
    region, about 65 MB for a 128 x 96 x 32 volume with 12 nodes.
    """

    __slots__ = ("_handle", "_diagram")

    def __init__(self, handle: Any, diagram: "Diagram"):
        self._handle = handle
        self._diagram = weakref.ref(diagram)

    @property
    def nbytes(self) -> int:
        """Bytes held by the kept searches."""
        return int(self._handle.nbytes)

    def __repr__(self) -> str:
        return f"<geovoronoi.ShapeState: Distance Ratio searches, {self.nbytes / 1e6:.1f} MB>"


class Cut:
    """A set of cut grid edges: the edges between neighbouring voxels that a cut separates (the
    library's ``cut_set``), made by :func:`cut_from_mesh` or :func:`cut_from_polylines`.

    A cut belongs to one grid (``shape``, ``spacing``, ``origin``, ``orientation``, all in
    array-axis order) and one ``connectivity``; :func:`voronoi` and :func:`update` accept it only
    on that grid. Memory is proportional to the cut's area (16 bytes per voxel that leaves a cut
    edge), whatever the volume. Cuts are immutable: :meth:`merge` (or ``a | b``) returns a new one.

    Attributes
    ----------
    shape, spacing, origin, orientation, connectivity
        The grid and connectivity the cut was made for.
    stats : dict
        What the construction examined (``primitives``, ``degenerate``, ``voxels_visited``,
        ``edges_tested``; the library's ``cut_stats``); empty for a merged cut.
    """

    __slots__ = ("_handle", "shape", "spacing", "origin", "orientation", "connectivity", "stats")

    def __init__(self, handle, shape, spacing, origin, orientation, connectivity, stats=None):
        self._handle = handle
        self.shape = tuple(int(x) for x in shape)
        self.spacing = spacing
        self.origin = origin
        self.orientation = orientation
        self.connectivity = connectivity
        self.stats = {} if stats is None else dict(stats)

    def __len__(self) -> int:
        """Number of cut edges."""
        return len(self._handle)

    def _check_compatible(self, other: "Cut") -> None:
        if not isinstance(other, Cut):
            raise TypeError(f"geovoronoi: expected a Cut, got {type(other).__name__}")
        if (other.shape != self.shape or other.spacing != self.spacing or other.origin != self.origin
                or not np.array_equal(other.orientation, self.orientation) or other.connectivity != self.connectivity):
            raise ValueError(f"geovoronoi: the two cuts belong to different grids or connectivities "
                             f"({self!r} and {other!r})")

    def merge(self, other: "Cut") -> "Cut":
        """A new cut holding the edges of both (same grid and connectivity)."""
        self._check_compatible(other)
        return Cut(self._handle._merge(other._handle), self.shape, self.spacing, self.origin, self.orientation,
                   self.connectivity)

    __or__ = merge

    def edges(self) -> np.ndarray:
        """The cut edges as an (m, 2) int64 array of flat C-order voxel indices ``(u, v)``
        (``np.unravel_index(edges, cut.shape)`` gives array indices); each edge once, u < v, sorted
        by u."""
        return self._handle._edges()

    def __eq__(self, other: Any) -> bool:
        if not isinstance(other, Cut):
            return NotImplemented
        try:
            self._check_compatible(other)
        except ValueError:
            return False
        return bool(self._handle._equal(other._handle))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Cut(edges={len(self)}, shape={self.shape}, connectivity={self.connectivity})"


# ---- argument normalisation ----------------------------------------------------------------------


class BranchingGrid(NamedTuple):
    """A branching (non-manifold) coarse grid over a fine 3D field (docs/branching.md), as
    :func:`branching_grid` returns it: one node, a *copy*, per connected piece of material (fine value
    > 0) in each coarse cell of ``factor**3`` fine voxels; copies of neighbouring cells are linked where
    their fine material touches. Copies are numbered by cell, then by their lowest fine voxel.

    Arrays per copy: ``cell`` (flat index of its coarse cell, C order over ``coarse_shape``),
    ``copy_voxel`` (flat index of its lowest fine voxel), ``voxel_count``, ``stiffness`` (the field's
    dtype; the ``reduction`` of its fine values). ``cell_begin`` (cells + 1): the copies of cell c are
    ``cell_begin[c]:cell_begin[c+1]``. Links in CSR form: the links of copy a are entries
    ``link_begin[a]:link_begin[a+1]`` of ``link_copy`` (the other copy, increasing) and ``link_dir``
    (the coarse stencil's direction index). ``fine_copy``: per fine voxel ``[z, y, x]`` its copy, -1
    outside the material. Coarse geometry in array-axis order.
    """

    factor: int
    connectivity: int
    reduction: str
    coarse_shape: Tuple[int, int, int]
    coarse_spacing: Tuple[float, float, float]
    coarse_origin: Tuple[float, float, float]
    cell: np.ndarray
    cell_begin: np.ndarray
    copy_voxel: np.ndarray
    voxel_count: np.ndarray
    stiffness: np.ndarray
    link_begin: np.ndarray
    link_copy: np.ndarray
    link_dir: np.ndarray
    fine_copy: np.ndarray

    @property
    def copies(self) -> int:
        """The number of copies (the graph's nodes)."""
        return int(self.cell.shape[0])


class BranchingDiagram(NamedTuple):
    """The Voronoi diagram on a branching grid (``voronoi(..., coarsen=N)``): per copy ``distance``,
    ``label`` (seed index, -1 unreachable) and ``parent`` (copy, -1 for seeds and unreachable copies),
    ``seed_copies`` (each seed's copy); the same painted on the fine grid, ``fine_distance`` and
    ``fine_label`` (``[z, y, x]``, +inf / -1 outside the material); and the ``grid``. What
    :func:`update` needs to update it after a cut: ``seeds`` (the seeds as fine voxels, ``[z, y, x]``),
    the fine grid's ``spacing``, ``origin`` and ``orientation``, the ``metric``, the ``cut`` it was
    solved with (None: none); ``stats``: for a diagram returned by :func:`update`, what the update did
    (``changed``: copies of the cells the cut changed, ``invalidated``: copies below them in the
    shortest-path forest, ``settled``: copies the re-solve settled); None for a solve."""

    grid: BranchingGrid
    distance: np.ndarray
    label: np.ndarray
    parent: np.ndarray
    seed_copies: np.ndarray
    fine_distance: np.ndarray
    fine_label: np.ndarray
    seeds: Optional[np.ndarray] = None
    spacing: Optional[Tuple[float, float, float]] = None
    origin: Optional[Tuple[float, float, float]] = None
    orientation: Optional[np.ndarray] = None
    metric: Optional[str] = None
    cut: Optional["Cut"] = None
    stats: Optional[dict] = None


class BranchingWeights(NamedTuple):
    """Shape functions on a branching grid (``shape_functions(..., coarsen=N)``, docs/branching.md).

    ``weights``: scipy.sparse.csr_array (copies x nodes), one row per copy in copy order (the rows
    of :class:`BranchingGrid`'s copies); ``node`` (int32) and ``weight`` (the field's dtype), shape
    ``(copies, k)``: the same rows in the fixed-K layout (slots by decreasing weight, empty ones -1 and
    0). ``fine``: the rows painted on the fine grid (fine voxels x nodes, C order of the field's
    voxels: every material voxel takes its copy's row, the others an empty row); ``fine_node`` and
    ``fine_weight``, shape ``field.shape + (k,)``: the same in the fixed-K layout, what SOFA's weight
    and index images hold (docs/branching.md, "SOFA layout"). ``diagram``: the
    :class:`BranchingDiagram` the weights belong to (its ``grid`` maps copies and fine voxels)."""

    diagram: BranchingDiagram
    weights: Any
    node: np.ndarray
    weight: np.ndarray
    fine: Any
    fine_node: np.ndarray
    fine_weight: np.ndarray


def _factor(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"geovoronoi: the coarsening factor must be an integer, got {value!r}")
    if value < 1 or value > 1 << 20:
        raise ValueError(f"geovoronoi: the coarsening factor must be from 1 to {1 << 20}, got {value}")
    return int(value)


def _reduction(value: Any) -> str:
    if value == "harmonic_mean":
        value = "harmonic"
    if value not in REDUCTIONS:
        raise ValueError(f"geovoronoi: reduction must be one of {', '.join(REDUCTIONS)}, got {value!r}")
    return str(value)


def branching_grid(field: Any, factor: int, *, connectivity: Optional[int] = None, reduction: str = "mean",
                   spacing: Any = None, origin: Any = None, orientation: Any = None) -> BranchingGrid:
    """The branching grid of the 3D ``field`` ``[z, y, x]`` coarsened by ``factor`` (docs/branching.md).

    Material is where the field is > 0 (NaN is empty). ``connectivity`` (6, 18 or 26, default 26) is
    used for the pieces inside a cell, for the fine contacts that link copies and for the coarse
    stencil. ``reduction``: a copy's stiffness from its fine values, one of :data:`REDUCTIONS`.
    ``spacing``, ``origin``, ``orientation``: the fine grid's, as for :func:`voronoi`; the coarse grid
    has spacing x factor and each cell centred on its fine voxels.

    Raises ValueError for a factor < 1, a field that is not 3D or has no material.
    """
    f = _field_array(field)
    if f.ndim != 3:
        raise ValueError(f"geovoronoi: branching grids need a 3D field, got {f.ndim} dimensions")
    sp = _axis_tuple(spacing, 3, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, 3, "origin", 0.0)
    _check_origin(org)
    orient = _orientation(orientation, 3)
    d = _ext._branching_grid(f, list(sp), list(org), [float(v) for v in np.ravel(orient)], _factor(factor),
                             _connectivity(connectivity, 3), _reduction(reduction))
    return BranchingGrid(**d)


def _check_material_seeds(f: np.ndarray, s: np.ndarray) -> None:
    values = f[tuple(s.T)]
    bad = ~(values > 0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"geovoronoi: seed {i} at {tuple(int(v) for v in s[i])} lies in empty material (field "
                         f"value {values[i]}), where the branching grid has no copy")


def _branching_diagram(d: dict, seeds: np.ndarray, sp, org, orient, m: str, cut: Optional["Cut"]) -> BranchingDiagram:
    d = {name: value for name, value in d.items() if name not in ("copy_weights", "fine_weights", "at")}
    d["grid"] = BranchingGrid(**d["grid"])
    return BranchingDiagram(**d, seeds=seeds, spacing=sp, origin=org, orientation=orient, metric=m, cut=cut)


def _branching_voronoi(f: np.ndarray, s: np.ndarray, sp, org, orient, m: str, conn: int, b: str, nthreads: int,
                       cb, factor: int, reduction: str, cut: Optional["Cut"] = None) -> BranchingDiagram:
    _check_material_seeds(f, s)
    if cut is not None:
        _check_cut(cut, f.shape, sp, org, orient, conn)
    d = _ext._branching_voronoi(f, list(sp), list(org), [float(v) for v in np.ravel(orient)], factor, conn,
                                _reduction(reduction), m, b, nthreads, s, cb, None if cut is None else cut._handle)
    return _branching_diagram(d, s, sp, org, orient, m, cut)


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


def _shape_options(method: Any, k: Any, batch_size: Any) -> Tuple[str, int, int]:
    """The method, k and batch_size of :func:`shape_functions` and :func:`update_shape_functions`."""
    if not isinstance(method, str):
        raise TypeError(f"geovoronoi: method must be a string ({', '.join(METHODS)}), got {method!r}")
    if method not in METHODS:
        raise ValueError(f"geovoronoi: unknown method {method!r} ({', '.join(METHODS)})")
    for name, value in (("k", k), ("batch_size", batch_size)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise TypeError(f"geovoronoi: {name} must be an integer, got {value!r}")
        if value < 1:
            raise ValueError(f"geovoronoi: {name} must be >= 1, got {value}")
    return method, int(k), int(batch_size)


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
            # the point as given, and the first array axis it leaves the grid along (never the voxel
            # it rounds to: far outside, that index means nothing)
            a = next(a for a in range(ndim) if not 0 <= idx[i, a] < shape[a])
            given = ", ".join(repr(float(v)) for v in x[i])
            raise ValueError(f"geovoronoi: {what[:-1]} {i} at world point ({given}) lies outside the grid: its "
                             f"nearest voxel centre has index {idx[i, a]:g} along array axis {a}, where the "
                             f"indices run 0 to {int(shape[a]) - 1}")
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
            parent: bool = False, cut: Optional["Cut"] = None, coarsen: Optional[int] = None,
            reduction: str = "mean") -> Union[Diagram, "BranchingDiagram"]:
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
        ``seq``: sequential Dijkstra; ``thrust``: Thrust on OpenMP threads (when built); ``auto``:
        the library's per-problem rule, as the C++ tool's default (``thrust`` when built, with more
        than one thread to use and a domain of at least 2**18 voxels filling at least 5 % of the
        grid; else ``seq``; :func:`shape_functions` drops the domain condition). Every backend gives
        the same result, bit for bit.
    threads : int, optional
        OpenMP threads for ``thrust`` (default: OpenMP's default); ``seq`` accepts only 1.
    progress : callable, optional
        Called with increments of the percentage done (they add up to 100), e.g.
        ``tqdm(total=100).update``, from the solver's progress hook (solve_options::progress); an
        exception it raises cancels the solve and propagates.
    parent : bool
        Also compute the parent (predecessor) image. A diagram that :func:`update` will update needs
        it (8 more bytes per voxel; no measurable extra time).
    cut : Cut, optional
        Solve with these grid edges removed (both directions): a cut separates two voxels without
        removing either. It must have been made for this grid (shape, spacing, origin, orientation)
        and connectivity. Every backend honours it, bitwise alike. The diagram remembers it
        (``Diagram.cut``), and so do :func:`shape_functions` and :func:`update`.
    coarsen : int, optional
        Solve on the branching grid of the 3D ``field`` coarsened by this factor
        (:func:`branching_grid`, docs/branching.md): seeds are fine voxels (or world points), each in
        the copy holding it; returns a :class:`BranchingDiagram` (per copy, and painted on the fine
        grid). A ``cut`` (made for the fine grid) splits the copies of the cells it crosses before the
        solve; ``backend="auto"`` runs ``seq``; ``parent`` is always computed.
    reduction : str
        With ``coarsen``: the copies' stiffness, one of :data:`REDUCTIONS` (default ``"mean"``).

    Returns
    -------
    Diagram, or BranchingDiagram with ``coarsen``

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
    if coarsen is not None:
        if ndim != 3:
            raise ValueError(f"geovoronoi: coarsen= (branching grids) needs a 3D field, got {ndim} dimensions")
        return _branching_voronoi(f, s, sp, org, orient, m, conn, b, nthreads, cb, _factor(coarsen), reduction, cut)
    _check_seeds(f, s, m)
    if cut is not None:
        _check_cut(cut, f.shape, sp, org, orient, conn)
    handle, distance, label, par, seed_idx = _ext._voronoi(f, list(sp), list(org), m, conn, b, nthreads, s, False,
                                                           bool(parent), cb, None if cut is None else cut._handle)
    return Diagram(handle, distance, label, par, seed_idx, sp, org, m, conn, mask_array, orient, cut)


def shape_functions(field: Any, seeds_or_diagram: Any, *, method: str, k: int = 4, points: Any = None,
                    world: bool = False, spacing: Any = None, origin: Any = None, orientation: Any = None,
                    metric: Optional[str] = None, connectivity: Optional[int] = None, mask: Any = None,
                    backend: str = "auto", threads: Optional[int] = None,
                    progress: Optional[Callable[[float], Any]] = None, fixed_k: bool = False,
                    batch_size: int = 4096, cut: Optional["Cut"] = None, keep_state: bool = False,
                    coarsen: Optional[int] = None, reduction: str = "mean"):
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
    cut : Cut, optional
        With seeds: solve and compute the weights with these edges cut (see :func:`voronoi`). A
        :class:`Diagram` carries its own cuts (``Diagram.cut``), which are always used.
    progress : callable, optional
        Called with increments of the percentage done (they add up to 100); a tqdm bar's
        ``update`` works with ``total=100``. An exception it raises cancels the computation and
        propagates. Ctrl-C cancels too (KeyboardInterrupt).
    keep_state : bool
        Distance Ratio on every voxel of a :class:`Diagram` only: also return a :class:`ShapeState`
        (the nodes' searches), which :func:`update_shape_functions` takes as ``state=`` to update
        the weights after a cut or a field edit in a fraction of the time (see ShapeState for its
        memory). The weights are the same either way.
    coarsen : int, optional
        The weights on the branching grid of the 3D ``field`` coarsened by this factor (as
        ``voronoi(..., coarsen=N)``, docs/branching.md), from seeds (fine voxels, or world points with
        ``world=True``; not a Diagram): returns a :class:`BranchingWeights` (one row per copy, and the
        rows painted on the fine grid). With ``points`` (fine voxels, or world points with
        ``world=True``): the rows of the copies holding them, as without ``coarsen`` (a point in
        empty material gets an empty row). ``cut``: made for the fine grid, it splits the copies of
        the cells it crosses. ``backend="auto"`` runs ``seq``; ``batch_size`` does not apply.
        ``coarsen=1`` gives the regular weights bit for bit.
    reduction : str
        With ``coarsen``: the copies' stiffness, one of :data:`REDUCTIONS` (default ``"mean"``).

    Other parameters are those of :func:`voronoi`.

    Returns
    -------
    scipy.sparse.csr_array, shape (voxels or points, nodes)
        Rows in C order of the field's voxels (``np.ravel_multi_index``), weights in the field's
        dtype; rows sum to 1 inside the domain, empty outside. With ``fixed_k=True``:
        ``(csr, indices, weights)``. With ``keep_state=True``: a pair (that, ShapeState). With
        ``coarsen`` and no ``points``: a :class:`BranchingWeights`.
    """
    import scipy.sparse

    method, k, batch_size = _shape_options(method, k, batch_size)
    if coarsen is not None:
        if keep_state:
            raise ValueError("geovoronoi: keep_state=True is not available with coarsen= (branching grids)")
        return _branching_shape_functions(field, seeds_or_diagram, method, k, points, bool(world), spacing, origin,
                                          orientation, metric, connectivity, mask, backend, threads,
                                          _progress(progress), bool(fixed_k), cut, _factor(coarsen),
                                          _reduction(reduction))
    keep_state = bool(keep_state)
    if keep_state and (method != "distance_ratio" or points is not None or not isinstance(seeds_or_diagram, Diagram)):
        raise ValueError("geovoronoi: keep_state=True needs method='distance_ratio', no points, and a Diagram "
                         "(the state belongs to it)")
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
        if cut is not None:
            raise ValueError("geovoronoi: pass the cut to voronoi(); a diagram carries its cuts (Diagram.cut)")
        if d._mask is not None:
            f = _apply_mask(f, d._mask)
    else:
        d = voronoi(f, seeds_or_diagram, spacing=spacing, origin=origin, orientation=orientation,
                    metric="min_stiffness" if metric is None else metric, connectivity=connectivity, mask=mask,
                    world=world, backend=backend, threads=threads, cut=cut)
        if d._mask is not None:
            f = _apply_mask(f, d._mask)
    qp = None
    if points is not None:
        qp = _points(points, ndim, bool(world), d.spacing, d.origin, f.shape, "points", d.orientation)
    (data, indices, indptr, nodes, fixed_idx, fixed_w), handle = _ext._shape_functions(
        f, list(d.spacing), list(d.origin), d.metric, d.connectivity, _backend(backend), _threads(threads),
        d._handle, method, k, batch_size, cb, None if qp is None else np.ascontiguousarray(qp, np.int64),
        keep_state)
    # with points, only those voxels are computed (the library's shape_functions_at): one row each
    w = scipy.sparse.csr_array((data, indices, indptr), shape=(f.size if qp is None else len(qp), int(nodes)))
    res = (w, fixed_idx, fixed_w) if fixed_k else w
    return (res, ShapeState(handle, d)) if keep_state else res


def _branching_shape_functions(field: Any, seeds: Any, method: str, k: int, points: Any, world: bool, spacing: Any,
                               origin: Any, orientation: Any, metric: Optional[str], connectivity: Any, mask: Any,
                               backend: Any, threads: Any, cb, fixed_k: bool, cut: Optional["Cut"], factor: int,
                               reduction: str):
    """shape_functions(..., coarsen=N): the arguments normalised as voronoi(..., coarsen=N) does."""
    import scipy.sparse

    if isinstance(seeds, (Diagram, BranchingDiagram)):
        raise ValueError("geovoronoi: coarsen= takes the seeds (fine voxels, or world points with world=True), "
                         "not a diagram")
    f = _field_array(field)
    if f.ndim != 3:
        raise ValueError(f"geovoronoi: coarsen= (branching grids) needs a 3D field, got {f.ndim} dimensions")
    sp = _axis_tuple(spacing, 3, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, 3, "origin", 0.0)
    _check_origin(org)
    orient = _orientation(orientation, 3)
    m = _metric("min_stiffness" if metric is None else metric)
    conn = _connectivity(connectivity, 3)
    b = _backend(backend)
    nthreads = _threads(threads)
    if mask is not None:
        f = _apply_mask(f, mask)
    s = _points(seeds, 3, world, sp, org, f.shape, "seeds", orient)
    _check_material_seeds(f, s)
    if cut is not None:
        _check_cut(cut, f.shape, sp, org, orient, conn)
    qp = None if points is None else _points(points, 3, world, sp, org, f.shape, "points", orient)
    d = _ext._branching_shape_functions(f, list(sp), list(org), [float(v) for v in np.ravel(orient)], factor, conn,
                                        reduction, m, b, nthreads, s, method, k, cb, qp,
                                        None if cut is None else cut._handle)
    if qp is not None:
        data, indices, indptr, nodes, fixed_idx, fixed_w = d["at"]
        w = scipy.sparse.csr_array((data, indices, indptr), shape=(len(qp), int(nodes)))
        return (w, fixed_idx, fixed_w) if fixed_k else w
    data, indices, indptr, nodes, node, weight = d["copy_weights"]
    copies = scipy.sparse.csr_array((data, indices, indptr), shape=(node.shape[0], int(nodes)))
    fdata, findices, findptr, _, fine_node, fine_weight = d["fine_weights"]
    fine = scipy.sparse.csr_array((fdata, findices, findptr), shape=(f.size, int(nodes)))
    return BranchingWeights(_branching_diagram(d, s, sp, org, orient, m, cut), copies, node, weight, fine, fine_node,
                            fine_weight)


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


# ---- cuts and incremental updates ---------------------------------------------------------------


def _grid_args(shape: Any, spacing: Any, origin: Any, orientation: Any, connectivity: Any, ndim: int):
    try:
        shp = tuple(int(x) for x in shape)
    except TypeError:
        raise TypeError(f"geovoronoi: shape must be a sequence of {ndim} integers, got {shape!r}") from None
    if len(shp) != ndim or any(x < 1 for x in shp):
        raise ValueError(f"geovoronoi: shape must have {ndim} positive entries (array-axis order), got {shape!r}")
    sp = _axis_tuple(spacing, ndim, "spacing", 1.0)
    _check_spacing(sp)
    org = _axis_tuple(origin, ndim, "origin", 0.0)
    _check_origin(org)
    return shp, sp, org, _orientation(orientation, ndim), _connectivity(connectivity, ndim)


def _check_cut(cut: Any, shape, spacing, origin, orientation, connectivity, what: str = "cut") -> None:
    if not isinstance(cut, Cut):
        raise TypeError(f"geovoronoi: {what} must be a geovoronoi.Cut, got {type(cut).__name__}")
    if cut.shape != tuple(shape):
        raise ValueError(f"geovoronoi: the {what} was made for shape {cut.shape}, the field has shape {tuple(shape)}")
    if cut.connectivity != connectivity:
        raise ValueError(f"geovoronoi: the {what} was made for connectivity {cut.connectivity}, the solve uses "
                         f"{connectivity}")
    if cut.spacing != tuple(spacing) or cut.origin != tuple(origin):
        raise ValueError(f"geovoronoi: the {what} was made for spacing {cut.spacing} and origin {cut.origin}, the "
                         f"solve uses {tuple(spacing)} and {tuple(origin)}")
    if not np.array_equal(cut.orientation, orientation):
        raise ValueError(f"geovoronoi: the {what} was made for orientation {cut.orientation.tolist()}, the solve uses "
                         f"{np.asarray(orientation).tolist()}")


def cut_from_mesh(vertices: Any, triangles: Any, *, shape: Sequence[int], spacing: Any = None, origin: Any = None,
                  orientation: Any = None, connectivity: Optional[int] = None) -> Cut:
    """The grid edges that a triangle mesh cuts (the library's ``cut_from_mesh``).

    An edge between two neighbouring voxels is cut when the closed segment between their centres
    meets a closed triangle (touching counts). Vertices are rounded once onto a lattice of 2^-16
    voxel, then every test is exact (docs/cuts.md).

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        World points in **array-axis order (z, y, x)**, like world seeds, ``spacing`` and
        ``origin``: world = origin + orientation @ (index * spacing). :func:`read_mesh` returns
        them in that order; a mesh in x, y, z columns (an STL file's) is ``vertices[:, ::-1]``.
    triangles : array_like of int, shape (m, 3)
        Vertex indices.
    shape : sequence of 3 ints
        The grid (the field's shape, ``[z, y, x]``).
    spacing, origin, orientation, connectivity
        As for :func:`voronoi`; the cut can only be used on that grid and connectivity.

    Returns
    -------
    Cut

    Raises
    ------
    ValueError
        A vertex that is not finite or lies more than 2^24 voxels from the grid, a triangle index
        out of range, bad shapes (the message names the vertex or triangle).
    """
    shp, sp, org, orient, conn = _grid_args(shape, spacing, origin, orientation, connectivity, 3)
    v = np.asarray(vertices)
    if v.dtype == object or v.dtype.kind not in "iuf":
        raise TypeError(f"geovoronoi: vertices must be a numeric (n, 3) array, got dtype {v.dtype}")
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"geovoronoi: vertices must be an (n, 3) array of world points (z, y, x), got shape {v.shape}")
    t = np.asarray(triangles)
    if t.size == 0:
        t = t.reshape(0, 3)
    if t.dtype == object or t.dtype.kind not in "iu":
        raise TypeError(f"geovoronoi: triangles must be an integer (m, 3) array, got dtype {t.dtype}")
    if t.ndim != 2 or t.shape[1] != 3:
        raise ValueError(f"geovoronoi: triangles must be an (m, 3) array of vertex indices, got shape {t.shape}")
    handle, stats = _ext._cut_from_mesh(np.ascontiguousarray(v, np.float64), np.ascontiguousarray(t, np.int64),
                                        list(shp), list(sp), list(org), [float(x) for x in orient.ravel()], conn)
    return Cut(handle, shp, sp, org, orient, conn, stats)


def cut_from_polylines(polylines: Any, *, shape: Sequence[int], spacing: Any = None, origin: Any = None,
                       orientation: Any = None, connectivity: Optional[int] = None) -> Cut:
    """The edges of a 2D grid that polylines cut (the library's ``cut_from_polylines``).

    ``polylines`` is a list of (n, 2) arrays of world points in array-axis order (y, x), or one
    such array; an edge is cut when its closed segment meets a polyline segment (touching counts),
    a polyline of one point cuts the edges through that point. Other parameters as
    :func:`cut_from_mesh` (``shape`` 2D, connectivity 4 or 8).
    """
    shp, sp, org, orient, conn = _grid_args(shape, spacing, origin, orientation, connectivity, 2)
    if isinstance(polylines, np.ndarray) and polylines.ndim == 2:
        polylines = [polylines]
    lines = []
    for i, line in enumerate(polylines):
        a = np.asarray(line)
        if a.dtype == object or a.dtype.kind not in "iuf":
            raise TypeError(f"geovoronoi: polyline {i} must be a numeric (n, 2) array, got dtype {a.dtype}")
        if a.ndim != 2 or a.shape[1] != 2 or a.shape[0] == 0:
            raise ValueError(f"geovoronoi: polyline {i} must be an (n, 2) array of world points (y, x) with n >= 1, "
                             f"got shape {a.shape}")
        lines.append(np.ascontiguousarray(a, np.float64))
    handle, stats = _ext._cut_from_polylines(lines, list(shp), list(sp), list(org), [float(x) for x in orient.ravel()],
                                             conn)
    return Cut(handle, shp, sp, org, orient, conn, stats)


def read_mesh(path: Union[str, os.PathLike]) -> Tuple[np.ndarray, np.ndarray]:
    """Read a triangle mesh: STL (ASCII or binary) or OBJ, by extension.

    Returns
    -------
    (vertices, triangles)
        ``vertices`` float64 (n, 3) in **array-axis order (z, y, x)**: the file's x, y, z columns
        reversed, ready for :func:`cut_from_mesh`; ``triangles`` int64 (m, 3) vertex indices.

    Raises
    ------
    OSError
        Missing, unreadable or malformed file, unknown extension (the message names the file).
    """
    v, t = _ext._read_mesh(os.fspath(path))
    return v, t


class Voxelization(NamedTuple):
    """What :func:`voxelize` returns: the images and their grid, ready for :func:`voronoi`
    (``gv.voronoi(v.stiffness, seeds, spacing=v.spacing, origin=v.origin,
    orientation=v.orientation)``)."""

    #: ``[z, y, x]``, float32 (or the ``dtype`` asked): the value of the part each voxel is inside,
    #: ``outside_value`` elsewhere.
    stiffness: np.ndarray
    #: ``[z, y, x]`` int32: the label of the part each voxel is inside, 0 elsewhere.
    labels: np.ndarray
    #: ``[z, y, x]`` float32 occupied fraction in [0, 1] with ``fraction=k > 0``, else None.
    fraction: Optional[np.ndarray]
    #: Voxel size per array axis (z, y, x).
    spacing: Tuple[float, float, float]
    #: World position of voxel 0's centre, per array axis (z, y, x).
    origin: Tuple[float, float, float]
    #: (3, 3) direction matrix in array-axis order (identity unless ``rotate=True``).
    orientation: np.ndarray
    #: ``triangles``, ``degenerate``, ``crossings``, ``inside_voxels``, ``mesh_volume``.
    stats: Dict[str, Any]


_OVERLAPS = ("last", "first", "max", "min", "error")


def _voxelize_part(item: Any, i: int) -> Tuple[np.ndarray, np.ndarray, float, int, str]:
    if isinstance(item, (str, os.PathLike)):
        mesh, value, label = item, 1.0, 0
    else:
        try:
            t = tuple(item)
        except TypeError:
            raise TypeError(f"geovoronoi: meshes[{i}] must be (mesh, value) or (mesh, value, label), got "
                            f"{item!r}") from None
        if len(t) not in (2, 3) or not isinstance(t[1], numbers.Real) or isinstance(t[1], bool):
            raise TypeError(f"geovoronoi: meshes[{i}] must be (mesh, value) or (mesh, value, label) with mesh a path or "
                            f"(vertices, triangles) and value a number")
        mesh, value = t[0], float(t[1])
        label = t[2] if len(t) == 3 else 0
        if label is None:
            label = 0
        if not isinstance(label, numbers.Integral) or isinstance(label, bool) or not 0 <= int(label) <= 2**31 - 1:
            raise ValueError(f"geovoronoi: meshes[{i}]: the label must be an integer from 1 to 2147483647 (0: the "
                             f"part's 1-based position), got {label!r}")
        label = int(label)
    if not math.isfinite(value):
        raise ValueError(f"geovoronoi: meshes[{i}]: the value {value} is not finite")
    if isinstance(mesh, (str, os.PathLike)):
        name = os.fspath(mesh)
        v, t = _ext._read_mesh(name)
    else:
        name = f"meshes[{i}]"
        try:
            v, t = mesh
        except (TypeError, ValueError):
            raise TypeError(f"geovoronoi: meshes[{i}]: the mesh must be a path or (vertices, triangles)") from None
        v, t = np.asarray(v), np.asarray(t)
        if v.dtype == object or v.dtype.kind not in "iuf" or v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"geovoronoi: meshes[{i}]: vertices must be a numeric (n, 3) array of world points "
                             f"(z, y, x), got shape {v.shape} dtype {v.dtype}")
        if t.size == 0:
            t = t.reshape(0, 3)
        if t.dtype == object or t.dtype.kind not in "iu" or t.ndim != 2 or t.shape[1] != 3:
            raise ValueError(f"geovoronoi: meshes[{i}]: triangles must be an integer (m, 3) array, got shape "
                             f"{t.shape} dtype {t.dtype}")
    return (np.ascontiguousarray(v, np.float64), np.ascontiguousarray(t, np.int64), value, label, name)


def voxelize(meshes: Sequence[Any], *, voxel_size: Any = None, voxels: Any = None, pad: int = 0,
             rotate: bool = False, winding: bool = False, overlap: str = "last", surface_inside: bool = False,
             fraction: int = 0, outside_value: float = 0.0, dtype: Any = np.float32) -> Voxelization:
    """Voxelize closed triangle meshes into a stiffness image and a label image (the library's
    ``voxelize``; the same images as ``geovoronoi voxelize``, bit for bit).

    A voxel belongs to a mesh when its centre is inside it, decided exactly: every vertex is
    snapped once to a lattice of 2^-16 voxel, every later test is integer arithmetic.

    Parameters
    ----------
    meshes : sequence
        The parts, each ``(mesh, value)`` or ``(mesh, value, label)`` (or a bare path: value 1):
        ``mesh`` a path to a .stl/.obj file or ``(vertices, triangles)`` with vertices (n, 3) world
        points in **array-axis order (z, y, x)** as :func:`read_mesh` returns them; ``value`` the
        stiffness inside; ``label`` an integer >= 1 (default: the part's 1-based position).
    voxel_size : float or sequence of 3, optional
        Voxel size per array axis (z, y, x). Exactly one of ``voxel_size`` and ``voxels``.
    voxels : sequence of 3 ints, optional
        Voxel counts (z, y, x) across the meshes' bounds.
    pad : int
        Voxels added outside the bounds on every side.
    rotate : bool
        Grid axes along the meshes' principal axes (see ``orientation`` of the result).
    winding : bool
        Accept any triangle soup: inside where the generalized winding number is >= 1/2. Without it
        a mesh must be closed, consistently oriented and free of self-intersections.
    overlap : str
        A voxel inside several parts takes the ``"last"``, ``"first"``, ``"max"`` or ``"min"``
        value's part, or ``"error"`` raises.
    surface_inside : bool
        Voxels the surface passes through count as inside too.
    fraction : int
        k > 0: also the occupied fraction of each voxel from k^3 samples.
    outside_value : float
        Stiffness of the voxels inside no part.
    dtype : float32 or float64
        Type of the stiffness image.

    Returns
    -------
    Voxelization

    Raises
    ------
    ValueError
        Neither or both of ``voxel_size`` and ``voxels``, an open or inconsistent mesh without
        ``winding`` (the message names the part and the edge), an overlap with ``overlap="error"``,
        a bad option.
    OSError
        A mesh file that is missing, unreadable or malformed.
    """
    if isinstance(meshes, (str, os.PathLike)) or not isinstance(meshes, Sequence):
        raise TypeError("geovoronoi: meshes must be a list of (mesh, value[, label]) parts")
    parts = [_voxelize_part(m, i) for i, m in enumerate(meshes)]
    if (voxel_size is None) == (voxels is None):
        raise ValueError("geovoronoi: give exactly one of voxel_size and voxels")
    size: list = []
    counts: list = []
    if voxel_size is not None:
        size = list(_axis_tuple(voxel_size, 3, "voxel_size", 1.0))
        for i, x in enumerate(size):
            if not (math.isfinite(x) and x > 0):
                raise ValueError(f"geovoronoi: voxel_size[{i}] is {x}; it must be finite and > 0")
    else:
        c = np.asarray(voxels)
        if c.dtype.kind not in "iu" or c.shape != (3,) or np.any(c < 1):
            raise ValueError(f"geovoronoi: voxels must be 3 positive integers (z, y, x), got {voxels!r}")
        counts = [int(x) for x in c]
    if not isinstance(pad, numbers.Integral) or isinstance(pad, bool) or pad < 0:
        raise ValueError(f"geovoronoi: pad must be an integer >= 0, got {pad!r}")
    if overlap not in _OVERLAPS:
        raise ValueError(f"geovoronoi: overlap must be one of {', '.join(_OVERLAPS)}, got {overlap!r}")
    if not isinstance(fraction, numbers.Integral) or isinstance(fraction, bool) or not 0 <= fraction <= 64:
        raise ValueError(f"geovoronoi: fraction must be an integer from 0 to 64, got {fraction!r}")
    outside = float(outside_value)
    if not math.isfinite(outside):
        raise ValueError(f"geovoronoi: outside_value is {outside}; it must be finite")
    dt = np.dtype(dtype)
    if dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise ValueError(f"geovoronoi: dtype must be float32 or float64, got {dt}")
    stiffness, labels, frac, spacing, origin, orientation, stats = _ext._voxelize(
        parts, size, counts, int(pad), bool(rotate), bool(winding), overlap, bool(surface_inside), int(fraction),
        outside, dt == np.dtype(np.float64))
    return Voxelization(stiffness, labels, frac, tuple(spacing), tuple(origin), orientation, dict(stats))


_NODE_KINDS = ("add", "remove", "move")


def _voxel_list(value: Any, shape, what: str) -> Optional[np.ndarray]:
    """Flat C-order int64 indices from an (m, ndim) index array or a boolean mask of ``shape``."""
    if value is None:
        return None
    a = np.asarray(value)
    ndim = len(shape)
    if a.dtype == np.bool_:
        if a.shape != tuple(shape):
            raise ValueError(f"geovoronoi: the {what} mask has shape {a.shape}, the field has shape {tuple(shape)}")
        return np.flatnonzero(a).astype(np.int64)
    if a.dtype == object or a.dtype.kind not in "iu":
        raise TypeError(f"geovoronoi: {what} must be a boolean mask or an integer (m, {ndim}) array of array "
                        f"indices, got dtype {a.dtype}")
    if a.size == 0:
        return np.zeros(0, np.int64)
    if a.ndim == 1 and a.shape[0] == ndim:
        a = a.reshape(1, ndim)
    if a.ndim != 2 or a.shape[1] != ndim:
        raise ValueError(f"geovoronoi: {what} must be a boolean mask or an (m, {ndim}) array of array indices, "
                         f"got shape {a.shape}")
    idx = a.astype(np.int64)
    bad = ~np.all((idx >= 0) & (idx < np.asarray(shape)), axis=1)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"geovoronoi: {what} voxel {i} at {tuple(int(x) for x in idx[i])} lies outside the array of "
                         f"shape {tuple(shape)}")
    return np.ravel_multi_index(tuple(idx.T), tuple(shape)).astype(np.int64)


def _voxel(value: Any, shape, what: str) -> list:
    try:
        c = [v for v in np.asarray(value).ravel()]
        if np.asarray(value).dtype.kind not in "iu":
            raise TypeError
    except TypeError:
        raise TypeError(f"geovoronoi: {what}: the voxel must be {len(shape)} integer array indices, got {value!r}") from None
    if len(c) != len(shape):
        raise ValueError(f"geovoronoi: {what}: the voxel must have {len(shape)} array indices, got {value!r}")
    c = [int(x) for x in c]
    if any(x < 0 or x >= n for x, n in zip(c, shape)):
        raise ValueError(f"geovoronoi: {what}: voxel {tuple(c)} lies outside the array of shape {tuple(shape)}")
    return c


def _position(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"geovoronoi: {what}: the position must be an integer, got {value!r}")
    if value < 0:
        raise ValueError(f"geovoronoi: {what}: the position must be >= 0, got {value}")
    return int(value)


def _node_edits(nodes: Any, shape) -> list:
    """[(kind 0/1/2, position or -1, voxel list)] from ("add", voxel[, position]), ("remove", position),
    ("move", position, voxel)."""
    if nodes is None:
        return []
    out = []
    for i, e in enumerate(nodes):
        what = f"node edit {i}"
        if not isinstance(e, (tuple, list)) or not e or not isinstance(e[0], str):
            raise TypeError(f"geovoronoi: {what} must be a tuple (\"add\", voxel[, position]), (\"remove\", position) "
                            f"or (\"move\", position, voxel), got {e!r}")
        kind = e[0]
        if kind not in _NODE_KINDS:
            raise ValueError(f"geovoronoi: {what}: unknown kind {kind!r} (add, remove or move)")
        if kind == "add":
            if len(e) not in (2, 3):
                raise ValueError(f"geovoronoi: {what}: expected (\"add\", voxel[, position]), got {e!r}")
            out.append((0, _position(e[2], what) if len(e) == 3 else -1, _voxel(e[1], shape, what)))
        elif kind == "remove":
            if len(e) != 2:
                raise ValueError(f"geovoronoi: {what}: expected (\"remove\", position), got {e!r}")
            out.append((1, _position(e[1], what), []))
        else:
            if len(e) != 3:
                raise ValueError(f"geovoronoi: {what}: expected (\"move\", position, voxel), got {e!r}")
            out.append((2, _position(e[1], what), _voxel(e[2], shape, what)))
    return out


class _Change:
    """A change normalised against the diagram before it (flat voxel lists, node edit tuples)."""

    __slots__ = ("cut", "all", "carved", "added", "restiffened", "nodes")

    def __init__(self, d: Diagram, cut, carved, added, restiffened, nodes):
        shape = d.shape
        if cut is not None:
            _check_cut(cut, shape, d.spacing, d.origin, d.orientation, d.connectivity)
        self.cut = cut
        self.all = cut if d.cut is None else (d.cut if cut is None else d.cut.merge(cut))
        self.carved = _voxel_list(carved, shape, "carved")
        self.added = _voxel_list(added, shape, "added")
        self.restiffened = _voxel_list(restiffened, shape, "restiffened")
        self.nodes = _node_edits(nodes, shape)

    def args(self):
        return (None if self.cut is None else self.cut._handle, None if self.all is None else self.all._handle,
                self.carved, self.added, self.restiffened, self.nodes)


def _field_like(field: Any, d: Diagram, what: str) -> np.ndarray:
    f = _field_array(field)
    if f.shape != d.shape:
        raise ValueError(f"geovoronoi: the {what} has shape {f.shape} but the diagram has shape {d.shape}")
    if f.dtype != d.distance.dtype:
        raise ValueError(f"geovoronoi: the diagram was computed on a {d.distance.dtype} field, the {what} is {f.dtype}")
    if d._mask is not None:
        f = _apply_mask(f, d._mask)
    return f


def _branching_update(d: BranchingDiagram, field: Any, cut: Optional[Cut]) -> BranchingDiagram:
    """update() of a BranchingDiagram after a cut of its fine image (the library's update on branching grids)."""
    if d.seeds is None:
        raise ValueError("geovoronoi: this BranchingDiagram does not carry its seeds; solve it with voronoi(..., coarsen=N)")
    if cut is None:
        raise ValueError("geovoronoi: update() of a BranchingDiagram takes a cut= (a Cut of the fine grid) and no other "
                         "change")
    f = _field_array(field)
    if f.shape != d.fine_label.shape or f.dtype != d.distance.dtype:
        raise ValueError(f"geovoronoi: the field ({f.shape}, {f.dtype}) is not the one the diagram was solved on "
                         f"({d.fine_label.shape}, {d.distance.dtype})")
    g = d.grid
    _check_cut(cut, f.shape, d.spacing, d.origin, d.orientation, g.connectivity)
    all_cuts = cut if d.cut is None else d.cut.merge(cut)
    r = _ext._branching_update(f, list(d.spacing), list(d.origin), [float(v) for v in np.ravel(d.orientation)],
                               g.factor, g.connectivity, g.reduction, d.metric, "seq", 0,
                               d.seeds, None if d.cut is None else d.cut._handle, all_cuts._handle, d.distance,
                               d.label, d.parent, d.seed_copies)
    stats = r.pop("stats")
    return _branching_diagram(r, d.seeds, d.spacing, d.origin, d.orientation, d.metric, all_cuts)._replace(stats=stats)


def update(diagram: Union[Diagram, BranchingDiagram], field_after: Any, *, cut: Optional[Cut] = None,
           carved: Any = None, added: Any = None, restiffened: Any = None,
           nodes: Optional[Sequence[tuple]] = None) -> Union[Diagram, BranchingDiagram]:
    """The diagram after a change of its problem, bitwise equal to a full solve of the changed
    problem, in work proportional to the region that changes (the library's ``update``).

    The result equals ``voronoi(field_after, new_seeds, cut=all_cuts, parent=True, ...)`` with
    the diagram's spacing, origin, orientation, metric, connectivity and mask, bit for bit
    (distances, labels, parents), where ``all_cuts`` is ``diagram.cut`` merged with ``cut`` and
    ``new_seeds`` is ``diagram.seeds`` with the node edits applied.

    A :class:`BranchingDiagram` (``voronoi(..., coarsen=N)``) takes a ``cut`` only (a Cut of the fine
    grid; no other change): the cut splits the copies of the cells it crosses, and the result, a
    BranchingDiagram on the cut grid (``result.cut``: every cut so far; ``result.stats``), equals
    ``voronoi(field, diagram.seeds, coarsen=N, cut=all_cuts, ...)`` bit for bit (the library's
    update on branching grids, docs/branching.md).

    Parameters
    ----------
    diagram : Diagram or BranchingDiagram
        Computed with ``parent=True`` (the update follows its shortest-path tree), by
        :func:`voronoi` or by an earlier :func:`update`. It is not modified.
    field_after : array_like
        The field after the change, same shape and dtype as the diagram's. It must differ from the
        field the diagram was solved on **exactly** at the voxels listed in ``carved``, ``added`` and
        ``restiffened`` (not checked: the field before is not kept; an unlisted change gives a wrong
        result). Editing the field in place and passing it again is fine.
    cut : Cut, optional
        Newly cut edges (made for the diagram's grid and connectivity); the result remembers every
        cut so far (``result.cut``).
    carved, added, restiffened : array_like, optional
        Voxels as an (m, ndim) array of array indices or a boolean mask of the field's shape.
        ``carved``: outside the domain after the change (field value <= 0 or NaN; < 0, NaN or inf
        for ``mean_cost``), and not a node; ``added``: inside the domain after the change;
        ``restiffened``: any new value (stiffer, softer, entering or leaving the domain).
    nodes : sequence of tuples, optional
        Node (seed) edits, applied in order; positions are those of the list as it stands when the
        edit applies, and labels are positions in the new list, as in a full solve:
        ``("add", voxel)`` appends a node, ``("add", voxel, position)`` inserts it before
        ``position``; ``("remove", position)``; ``("move", position, voxel)`` moves a node, keeping
        its label. Voxels are array indices.

    Returns
    -------
    Diagram
        With parents, ``cut`` = every cut so far, and ``stats``: a dict of what the update did
        (``invalidated``, ``settled``, ``reparented``, ``lowered``, ...).

    Raises
    ------
    ValueError
        The diagram has no parents; shapes, dtypes, the cut's grid or connectivity differ; a listed
        voxel lies outside the grid; a carved voxel is still inside the domain or is a node; an added
        voxel is outside the domain; a node edit names a position beyond the list; the new node list
        has a node on a masked voxel or two nodes on one voxel (the library's messages).
    TypeError
        Arguments of the wrong type.

    Notes
    -----
    The update is the library's single-threaded host algorithm (the same for every backend); the
    GIL is released while it runs. It reports no progress.
    """
    if isinstance(diagram, BranchingDiagram):
        if carved is not None or added is not None or restiffened is not None or nodes is not None:
            raise ValueError("geovoronoi: update() of a BranchingDiagram takes a cut= only (no carved, added, "
                             "restiffened or nodes)")
        return _branching_update(diagram, field_after, cut)
    if not isinstance(diagram, Diagram):
        raise TypeError(f"geovoronoi: update needs a Diagram, got {type(diagram).__name__}")
    d = diagram
    if d.parent is None:
        raise ValueError("geovoronoi: update needs a diagram with parents; compute it with voronoi(..., parent=True)")
    f = _field_like(field_after, d, "field after the change")
    ch = _Change(d, cut, carved, added, restiffened, nodes)
    (handle, distance, label, par, seed_idx), stats = _ext._update(f, list(d.spacing), list(d.origin), d.metric,
                                                                   d.connectivity, d._handle, *ch.args())
    out = Diagram(handle, distance, label, par, seed_idx, d.spacing, d.origin, d.metric, d.connectivity, d._mask,
                  d.orientation, ch.all)
    out.stats = dict(stats)
    out._change = (weakref.ref(d), ch)
    return out


def _fixed_k_weights(weights: Any, k: int, rows: int, nodes: int, dtype) -> Tuple[np.ndarray, np.ndarray, int]:
    """(indices int32 (rows, k), weights (rows, k), node count) from a CSR or the fixed-K layout."""
    import scipy.sparse

    if isinstance(weights, tuple) and len(weights) == 3 and scipy.sparse.issparse(weights[0]):
        weights = weights[1:]  # shape_functions(..., fixed_k=True)'s triple: use the fixed-K layout
    if isinstance(weights, tuple):
        if len(weights) != 2:
            raise ValueError("geovoronoi: weights must be a scipy.sparse array, the (indices, weights) pair of the "
                             "fixed-K layout or shape_functions(..., fixed_k=True)'s triple")
        idx, w = (np.asarray(a) for a in weights)
        if idx.shape != w.shape or idx.ndim < 2 or idx.shape[-1] != k or idx.size != rows * k:
            raise ValueError(f"geovoronoi: the fixed-K weights have shapes {idx.shape} and {w.shape}; expected "
                             f"{rows} rows of k={k} slots")
        if w.dtype != dtype:
            raise ValueError(f"geovoronoi: the weights are {w.dtype}, the field is {dtype}")
        return (np.ascontiguousarray(idx.reshape(rows, k), np.int32), np.ascontiguousarray(w.reshape(rows, k)),
                nodes)
    if not scipy.sparse.issparse(weights):
        raise TypeError(f"geovoronoi: weights must be a scipy.sparse array or an (indices, weights) pair, got "
                        f"{type(weights).__name__}")
    csr = scipy.sparse.csr_array(weights)
    if csr.shape[0] != rows:
        raise ValueError(f"geovoronoi: the weights have {csr.shape[0]} rows, expected {rows}")
    if csr.dtype != dtype:
        raise ValueError(f"geovoronoi: the weights are {csr.dtype}, the field is {dtype}")
    counts = np.diff(csr.indptr)
    if counts.size and counts.max() > k:
        raise ValueError(f"geovoronoi: a row of the weights has {int(counts.max())} entries, more than k={k}")
    # the library's slot order: larger weight first, ties to the lower node (a function of the stored
    # values, so the fixed-K layout is rebuilt exactly)
    row = np.repeat(np.arange(rows), counts)
    order = np.lexsort((csr.indices, -csr.data.astype(np.float64), row))
    slot = np.arange(order.size) - csr.indptr[row]
    idx = np.full((rows, k), -1, np.int32)
    w = np.zeros((rows, k), dtype)
    idx[row, slot] = csr.indices[order]
    w[row, slot] = csr.data[order]
    return idx, w, int(csr.shape[1])


def update_shape_functions(weights: Any, diagram_before: Diagram, diagram_after: Diagram, field_after: Any, *,
                           method: str, k: int = 4, cut: Optional[Cut] = None, carved: Any = None,
                           added: Any = None, restiffened: Any = None, nodes: Optional[Sequence[tuple]] = None,
                           points: Any = None, world: bool = False, backend: str = "auto",
                           threads: Optional[int] = None, progress: Optional[Callable[[float], Any]] = None,
                           fixed_k: bool = False, batch_size: int = 4096, stats: bool = False,
                           state: Optional[ShapeState] = None):
    """Shape functions after a change, bitwise equal to
    ``shape_functions(field_after, diagram_after, method=method, k=k)`` (or its ``points=`` form),
    recomputing only the rows whose weights can change (the library's ``update_shape_functions``).

    Parameters
    ----------
    weights : scipy.sparse array, or (indices, weights), or shape_functions(..., fixed_k=True)'s triple
        The shape functions of ``diagram_before`` with the same ``method``, ``k`` (and ``points``).
        The method is not stored in the weights, so it cannot be checked.
    diagram_before, diagram_after : Diagram
        The diagrams before and after the change; ``diagram_after`` typically
        ``update(diagram_before, field_after, ...)``, or a full solve of the changed problem.
    field_after : array_like
        The field after the change.
    cut, carved, added, restiffened, nodes
        The change, as for :func:`update`. Leave them all out when ``diagram_after`` was returned by
        ``update(diagram_before, ...)``: the change it recorded is used.
    points, world, method, k, backend, threads, progress, fixed_k, batch_size
        As for :func:`shape_functions` (``points``: the points ``weights`` were computed at).
    stats : bool
        Also return what the update did: ``rows``, ``recomputed``, ``changed``, ``changed_voxels``,
        ``region_voxels``, ``nodes_affected``, ``full`` (the library's ``shape_update_stats``).
    state : ShapeState, optional
        Distance Ratio on every voxel: the state of ``weights`` (from ``shape_functions(...,
        keep_state=True)`` or an earlier update with ``state=``), computed on ``diagram_before``.
        The update repairs the nodes' searches around the change instead of running them again
        (node edits recompute every row and keep the searches anew), and returns the state of the
        new weights. The weights are the same with or without it.

    Returns
    -------
    As :func:`shape_functions`; with ``state`` a pair (that, the new ShapeState); with ``stats=True``
    the dict of what the update did is appended: (that, dict) or (that, ShapeState, dict).
    """
    for name, dd in (("diagram_before", diagram_before), ("diagram_after", diagram_after)):
        if not isinstance(dd, Diagram):
            raise TypeError(f"geovoronoi: {name} must be a Diagram, got {type(dd).__name__}")
    db, da = diagram_before, diagram_after
    if (da.shape != db.shape or da.spacing != db.spacing or da.origin != db.origin or da.metric != db.metric
            or da.connectivity != db.connectivity or not np.array_equal(da.orientation, db.orientation)
            or da.distance.dtype != db.distance.dtype):
        raise ValueError("geovoronoi: the diagrams before and after the change differ in shape, dtype, spacing, "
                         "origin, orientation, metric or connectivity")
    method, k, batch_size = _shape_options(method, k, batch_size)
    if state is not None:
        if not isinstance(state, ShapeState):
            raise TypeError(f"geovoronoi: state must be a ShapeState, got {type(state).__name__}")
        if method != "distance_ratio" or points is not None:
            raise ValueError("geovoronoi: a ShapeState applies to method='distance_ratio' on every voxel (no points)")
        if state._diagram() is not db:
            raise ValueError("geovoronoi: the ShapeState was computed on another diagram than diagram_before")
    cb = _progress(progress)
    f = _field_like(field_after, da, "field after the change")
    given = any(x is not None for x in (cut, carved, added, restiffened, nodes))
    if not given and da._change is not None and da._change[0]() is db:
        ch = da._change[1]
    else:
        ch = _Change(db, cut, carved, added, restiffened, nodes)
        if not ((ch.all is None and (da.cut is None or len(da.cut) == 0)) or
                (ch.all is not None and da.cut is not None and ch.all == da.cut)):
            raise ValueError("geovoronoi: diagram_after's cuts are not diagram_before's with the change's cut added")
    qp = None
    rows = f.size
    if points is not None:
        qp = np.ascontiguousarray(_points(points, f.ndim, bool(world), da.spacing, da.origin, f.shape, "points",
                                          da.orientation), np.int64)
        rows = len(qp)
    idx, w, ncols = _fixed_k_weights(weights, k, rows, len(db.seeds), f.dtype)
    (data, indices, indptr, nnodes, fixed_idx, fixed_w), st, handle = _ext._update_shape_functions(
        f, list(da.spacing), list(da.origin), da.metric, da.connectivity, _backend(backend), _threads(threads),
        db._handle, da._handle, *ch.args(), method, k, batch_size, cb, idx, w, ncols, qp,
        None if state is None else state._handle)
    import scipy.sparse

    res = scipy.sparse.csr_array((data, indices, indptr), shape=(rows, int(nnodes)))
    if fixed_k:
        if qp is None:
            fixed_idx = fixed_idx.reshape(f.shape + (k,))
            fixed_w = fixed_w.reshape(f.shape + (k,))
        res = (res, fixed_idx, fixed_w)
    out = (res,)
    if state is not None:
        out += (ShapeState(handle, da),)
    if stats:
        out += (dict(st),)
    return out if len(out) > 1 else res


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

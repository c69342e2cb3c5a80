"""``python -m geovoronoi``: the command-line tool's ``voronoi``, ``shape-functions``, ``cut`` and
``backends`` commands over the Python API.

It reads the same inputs as the C++ tool (a MetaImage stiffness volume, a CSV of seeds ``i,j,k`` in
x, y, z voxel order, or world ``x,y,z`` with ``--world``, cut meshes in ``.stl``/``.obj``) and
writes the same MetaImage, VTK and NumPy outputs, with the same contents bit for bit. Differences
from the C++ tool (docs/python.md): no PNG pictures (``labels.png``, ``distance.png``,
``weight_node<N>.png``, ``cut.png``: the Python API has no picture renderer), no ``demo``,
``--extrude``, ``--precision`` or ``--at``, only MetaImage input (``.mhd``/``.mha``), no CUDA
backend; the output folder is written in place (the C++ tool renames a finished temporary folder).
Exit codes as the C++ tool: 0 success, 2 bad input (one line on stderr), 1 anything else.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import time

import numpy as np

import geovoronoi as gv


class _UsageError(Exception):
    """Bad input or usage: one line, exit code 2."""


class _Failure(Exception):
    """The input was fine, the run was not: one line, exit code 1."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2, like the C++ tool
        raise _UsageError(message)


class _Once(argparse.Action):
    """An option that may be given once (the C++ tool refuses a repeated option)."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_given", set())
        if self.dest in seen:
            raise _UsageError(f"option {option_string} given twice")
        seen.add(self.dest)
        setattr(namespace, self.dest, values)


def _read_seeds(path: str, world: bool, shape_xyz):
    """Rows of the seed CSV as (n, 3) x, y, z numbers (the C++ tool's format), and each row's line."""
    try:
        with open(path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
    except OSError:
        raise _UsageError(f"{path}: cannot open the seed file") from None
    rows, lines = [], []
    for line_no, line in enumerate(text.split("\n"), start=1):
        line = line.split("#", 1)[0].replace("\t", " ").replace("\r", " ")
        if not line.strip():
            continue
        fields = [x.strip() for x in line.split(",")]
        if len(fields) > 3:
            raise _UsageError(f"{path}:{line_no}: more than 3 values")
        values = []
        for fld in fields:
            try:
                v = float(fld)
            except ValueError:
                v = math.nan
            if not fld or not math.isfinite(v):
                raise _UsageError(f"{path}:{line_no}: '{fld}' is not a number")
            if not world and (v != math.floor(v) or any(c in fld for c in ".eE")):
                raise _UsageError(f"{path}:{line_no}: '{fld}' is not an integer voxel index "
                                  "(use --world for physical coordinates)")
            values.append(v)
        if len(values) < 2:
            raise _UsageError(f"{path}:{line_no}: expected i,j,k (3 comma-separated values)")
        if len(values) == 2:
            if shape_xyz[2] != 1:
                raise _UsageError(f"{path}:{line_no}: seed has 2 values but the volume has {shape_xyz[2]} slices")
            values.append(0.0)
        rows.append(values)
        lines.append(line_no)
    if not rows:
        raise _UsageError(f"{path}: no seeds in the file")
    return np.array(rows, dtype=np.float64), lines


# strtoll's and strtod's syntax (leading white space, a sign; no trailing characters), which the C++
# tool's integer options and --carve accept; Python's int() and float() would take more ("1_0", "inf ")
_INTEGER = re.compile(r"[ \t\n\v\f\r]*[+-]?[0-9]+")
_DECIMAL = re.compile(r"[ \t\n\v\f\r]*[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


def _integer(args, name: str, fallback: int, lo: int, hi: int) -> int:
    """Option ``--name`` as an integer in [lo, hi] (the C++ tool's rule and message)."""
    value = getattr(args, name[2:].replace("-", "_"))
    if value is None:
        return fallback
    if not _INTEGER.fullmatch(value) or not lo <= int(value) <= hi:
        raise _UsageError(f"option {name} must be an integer from {lo} to {hi}, got '{value}'")
    return int(value)


def _load(args):
    """The field (float32, 3D), its geometry in array-axis order, the seeds (z, y, x) and their lines."""
    ext = os.path.splitext(args.stiffness)[1].lower()
    if ext not in (".mhd", ".mha"):
        raise _UsageError(f"{args.stiffness}: python -m geovoronoi reads MetaImage (.mhd/.mha) only")
    arr, spacing, origin, orientation = gv.read_image(args.stiffness)
    if arr.ndim == 4 or (arr.ndim == 3 and len(spacing) == 2):
        raise _UsageError(f"{args.stiffness}: has several channels; a stiffness image needs 1")
    # The C++ tool reads the volume as float32 and treats 2D images as one slice of a 3D volume.
    field = np.ascontiguousarray(arr, dtype=np.float32)
    if field.ndim == 2:
        field = field[np.newaxis]
        spacing, origin = (1.0,) + tuple(spacing), (0.0,) + tuple(origin)
        # one slice of a 3D volume: the slice axis keeps its own direction (the C++ tool's rule)
        o3 = np.eye(3)
        o3[1:, 1:] = orientation
        orientation = o3
    if field.ndim != 3:
        raise _UsageError(f"{args.stiffness}: expected a 2D or 3D image")
    xyz, lines = _read_seeds(args.seeds, args.world, field.shape[::-1])
    seeds = xyz[:, ::-1]  # x, y, z -> array order z, y, x
    if not args.world:
        seeds = seeds.astype(np.int64)
    return field, tuple(spacing), tuple(origin), np.asarray(orientation, dtype=np.float64), seeds, lines


def _load_cuts(paths, field, spacing, origin, orientation, connectivity):
    """The union of the cuts of every ``--cut MESH`` (None without one), as the C++ tool merges them."""
    cut = None
    for mesh in paths:
        if os.path.splitext(mesh)[1].lower() not in (".stl", ".obj"):
            raise _UsageError(f"{mesh}: --cut takes a .stl or .obj mesh")
        vertices, triangles = gv.read_mesh(mesh)
        try:
            c = gv.cut_from_mesh(vertices, triangles, shape=field.shape, spacing=spacing, origin=origin,
                                 orientation=orientation, connectivity=connectivity)
        except ValueError as e:
            raise _UsageError(f"{mesh}: {_strip(str(e))}") from None
        cut = c if cut is None else cut.merge(c)
    return cut


def _check_out(out: str) -> None:
    """--out must be a folder or a name whose parent folder exists (checked before any work)."""
    if not out:
        raise _UsageError("--out needs a folder name")
    if os.path.exists(out) and not os.path.isdir(out):
        raise _UsageError(f"{out}: exists and is not a folder")
    parent = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(parent):
        raise _UsageError(f"{out}: the parent folder {parent} does not exist")


def _common(p):
    p.add_argument("--stiffness", required=True, action=_Once, metavar="FILE",
                   help="the field: a MetaImage file (.mhd/.mha), read as float32")
    p.add_argument("--seeds", required=True, action=_Once, metavar="FILE",
                   help="CSV, one seed per line: i,j,k voxel indices (x,y,z with --world)")
    p.add_argument("--metric", default="min_stiffness", action=_Once, metavar="M",
                   help="min_stiffness, mean_stiffness, mean_cost or uniform (default: min_stiffness)")
    p.add_argument("--connectivity", action=_Once, metavar="N", help="6, 18 or 26 neighbours (default: 26)")
    p.add_argument("--backend", default="auto", action=_Once, metavar="B",
                   help="seq or thrust (default: auto, thrust on more than one hardware thread)")
    p.add_argument("--threads", action=_Once, metavar="N",
                   help="OpenMP threads of the thrust backend, 1 to 4 x the hardware threads; no effect on seq")
    p.add_argument("--world", action="store_true", help="seed coordinates (and cut's --carve box) are physical x,y,z")
    p.add_argument("--cut", action="append", default=[], metavar="MESH",
                   help="a cut surface, .stl or .obj in world coordinates; repeatable")
    p.add_argument("--out", required=True, action=_Once, metavar="DIR", help="the output folder")


def _add_shape_options(p, required: bool):
    p.add_argument("--method", required=required, action=_Once, metavar="M", help="distance-ratio, sibson or laplace")
    p.add_argument("--nodes-per-voxel", action=_Once, metavar="K", help="1..64 (default: 4)")
    p.add_argument("--picture-node", action=_Once, metavar="N",
                   help="checked like the C++ tool's (less than the number of seeds), but no picture is written")


def _shape_args(args, nseeds):
    """(method with underscores, K) from --method, --nodes-per-voxel, --picture-node (checked)."""
    method = args.method.replace("-", "_")
    if method not in gv.METHODS:
        raise _UsageError(f"unknown method '{args.method}' (distance-ratio, sibson or laplace)")
    k = _integer(args, "--nodes-per-voxel", 4, 1, 64)
    node = _integer(args, "--picture-node", 0, 0, 1 << 30)
    if node >= nseeds:
        raise _UsageError(f"--picture-node {node}: must be less than the number of nodes ({nseeds})")
    return method, k


def _threads(args, backend: str):
    """--threads N for the thrust backend (None: OpenMP's default); seq runs on one thread whatever N."""
    n = _integer(args, "--threads", 0, 1, 4 * (os.cpu_count() or 1))
    return n if n and backend == "thrust" else None


def _write_voronoi(out, d, field, spacing, origin, orientation):
    gv.write_image(os.path.join(out, "distance.mhd"), d.distance, spacing, origin, orientation)
    gv.write_image(os.path.join(out, "label.mhd"), d.label, spacing, origin, orientation)
    gv.write_vti(os.path.join(out, "voronoi.vti"), {"label": d.label, "distance": d.distance, "stiffness": field},
                 spacing, origin, orientation)


def _write_shape(out, w, idx, wt, label, spacing, origin, orientation):
    # The CLI's files: node index + 1 (0: none) as uint32 and weights as float32, K channels
    # interleaved (what MetaImage readers expect) and, for SOFA, planar; ParaView's weights.vti
    nodes = np.where(idx >= 0, idx + 1, 0).astype(np.uint32)
    weights = np.where(idx >= 0, wt, 0).astype(np.float32)
    for suffix, planar in (("_sofa_planar", True), ("", False)):
        gv.write_image(os.path.join(out, f"indices{suffix}.mhd"), nodes, spacing, origin, orientation,
                       channels=True, planar=planar)
        gv.write_image(os.path.join(out, f"weights{suffix}.mhd"), weights, spacing, origin, orientation,
                       channels=True, planar=planar)
    gv.write_vti(os.path.join(out, "weights.vti"),
                 {"label": label, "weights": weights, "nodes": np.where(idx >= 0, idx, -1).astype(np.int32)},
                 spacing, origin, orientation)
    w = w.astype(np.float32)
    np.save(os.path.join(out, "weights_indptr.npy"), w.indptr.astype(np.int64))
    np.save(os.path.join(out, "weights_indices.npy"), w.indices.astype(np.int32))
    np.save(os.path.join(out, "weights_data.npy"), w.data.astype(np.float32))


def _bits(a: np.ndarray) -> np.ndarray:
    """The array's bytes as unsigned integers, to compare floats bit for bit."""
    return a.view(f"u{a.dtype.itemsize}")


# ---- cut ------------------------------------------------------------------------------------------


def _parse_carve(text: str, world: bool, shape, spacing, origin, orientation) -> np.ndarray:
    """``--carve x0:x1,y0:y1,z0:z1`` as a boolean mask of the grid (array order), with the C++ tool's
    rules and messages: voxel indices with both ends included, or with ``world`` world coordinates of
    a closed box taking every voxel whose centre lies in it (computed as grid::world does, so the
    same voxels at the box's faces)."""
    what = f"--carve '{text}'"
    extent = shape[::-1]  # x, y, z
    ranges = []
    pos = 0
    for a, axis in enumerate("xyz"):
        comma = text.find(",", pos)
        if (a < 2) != (comma != -1):
            raise _UsageError(f"{what}: expected three ranges " + ("X0:X1,Y0:Y1,Z0:Z1 (world coordinates)" if world
                                                                   else "x0:x1,y0:y1,z0:z1 (voxel indices)"))
        part = text[pos:] if comma == -1 else text[pos:comma]
        colon = part.find(":")
        if colon == -1 or part.find(":", colon + 1) != -1:
            raise _UsageError(f"{what}: the {axis} range '{part}' is not FROM:TO")
        ends = []
        for num in (part[:colon], part[colon + 1:]):
            if world:
                if not _DECIMAL.fullmatch(num) or not math.isfinite(float(num)):
                    raise _UsageError(f"{what}: '{num}' in the {axis} range is not a finite number")
                ends.append(float(num))
            else:
                if not _INTEGER.fullmatch(num):
                    raise _UsageError(f"{what}: '{num}' in the {axis} range is not a voxel index (integer; world "
                                      "coordinates need --world)")
                ends.append(int(num))
        if ends[0] > ends[1]:
            raise _UsageError(f"{what}: the {axis} range runs backwards (FROM must be <= TO)")
        if not world and (ends[0] < 0 or ends[1] >= extent[a]):
            raise _UsageError(f"{what}: the {axis} range leaves the grid (indices 0 to {extent[a] - 1})")
        ranges.append(ends)
        pos = comma + 1
    mask = np.zeros(shape, dtype=bool)
    if world:
        # world position of every voxel centre, axis r (x, y, z): origin_r + sum over index axes a
        # (x, y, z order, zero entries skipped) of D[r, a] * (i_a * spacing_a), as grid::world
        d = np.asarray(orientation)[::-1, ::-1]  # array-axis order -> x, y, z
        sp, org = spacing[::-1], origin[::-1]
        index = [np.arange(n, dtype=np.float64).reshape([-1 if b == 2 - a else 1 for b in range(3)]) for a, n in
                 enumerate(extent)]
        mask[...] = True
        for r in range(3):
            s = np.zeros(shape)
            for a in range(3):
                if d[r, a] != 0.0:
                    s = s + d[r, a] * (index[a] * sp[a])
            p = org[r] + s
            mask &= (p >= ranges[r][0]) & (p <= ranges[r][1])
    else:
        (x0, x1), (y0, y1), (z0, z1) = ranges
        mask[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1] = True
    if not mask.any():
        raise _UsageError(f"{what}: the box holds no voxel centre of the grid")
    return mask


def _require_same_diagram(upd, full) -> None:
    """The update's promise: the updated diagram is the full recompute bit for bit; else exit 1."""
    for what, a, b in (("distance", _bits(upd.distance), _bits(full.distance)), ("label", upd.label, full.label),
                       ("parent", upd.parent, full.parent)):
        bad = np.flatnonzero(a.ravel() != b.ravel())
        if bad.size:
            v = np.unravel_index(bad[0], upd.shape)
            raise _Failure(f"internal error: the incremental update differs from the full recompute in its {what} "
                           f"at voxel ({v[2]},{v[1]},{v[0]}) (distance {upd.distance[v]:.9g} vs "
                           f"{full.distance[v]:.9g}, label {upd.label[v]} vs {full.label[v]}); please report this "
                           "with the inputs")


def _require_same_weights(upd, full) -> None:
    """The shape-function update's promise: the same node and weight bits in every slot; else exit 1."""
    (_, ui, uw), (_, fi, fw) = upd, full
    bad = np.flatnonzero((ui != fi).ravel() | (_bits(uw) != _bits(fw)).ravel())
    if bad.size:
        k = ui.shape[-1]
        v = np.unravel_index(bad[0] // k, ui.shape[:-1])
        s = (*v, bad[0] % k)
        raise _Failure(f"internal error: the updated shape functions differ from the full recompute at voxel "
                       f"({v[2]},{v[1]},{v[0]}) slot {s[-1]} (node {ui[s]} vs {fi[s]}, weight {uw[s]:.9g} vs "
                       f"{fw[s]:.9g}); please report this with the inputs")


def _cut(args, field, spacing, origin, orientation, seeds, lines, cut, threads, backend, shape):
    """geovoronoi cut: the diagram (and with --method the shape functions) before and after the change,
    the one after from the library's update, checked bit for bit against a full recompute."""
    carve = None
    if args.carve is not None:
        carve = _parse_carve(args.carve, args.world, field.shape, spacing, origin, orientation)
        voxels = (gv._points(seeds, 3, True, spacing, origin, field.shape, "seeds", orientation) if args.world
                  else seeds)
        for i, v in enumerate(voxels):
            if all(0 <= c < n for c, n in zip(v, field.shape)) and carve[tuple(v)]:
                raise _UsageError(f"--carve '{args.carve}' removes the seed on line {lines[i]} of {args.seeds} "
                                  "(a node cannot be carved; remove it from the seed file)")
    _check_out(args.out)
    after_field = field
    if carve is not None:  # -1 is outside under every metric's domain rule
        after_field = field.copy()
        after_field[carve] = -1
    kw = dict(spacing=spacing, origin=origin, orientation=orientation, metric=args.metric,
              connectivity=args.connectivity, backend=args.backend, threads=threads, world=args.world, parent=True)
    before = gv.voronoi(field, seeds, **kw)
    t0 = time.perf_counter()
    full = gv.voronoi(after_field, seeds, cut=cut, **kw)
    t_full = time.perf_counter() - t0
    # the update, as the C++ tool runs it: the cut edges, then the carving
    t0 = time.perf_counter()
    upd, invalidated = before, 0
    if cut is not None:
        upd = gv.update(upd, field, cut=cut)
        invalidated += upd.stats["invalidated"]
    if carve is not None:
        upd = gv.update(upd, after_field, carved=carve)
        invalidated += upd.stats["invalidated"]
    t_update = time.perf_counter() - t0
    _require_same_diagram(upd, full)
    changed = ((_bits(before.distance) != _bits(upd.distance)) | (before.label != upd.label)).astype(np.uint8)
    n_carved = 0 if carve is None else int(np.count_nonzero(carve))
    print(f"geovoronoi cut: {0 if cut is None else len(cut)} cut edges from {len(args.cut)} mesh(es), {n_carved} "
          f"carved voxels; {int(np.count_nonzero(changed))} voxels changed")
    print(f"  incremental update {t_update:9.4f} s  (library update(), host; {invalidated} voxels re-solved)")
    print(f"  full recompute     {t_full:9.4f} s  (backend {backend}, with parents)  "
          f"{t_full / t_update if t_update > 0 else 0.0:.1f}x; identical bit for bit (distance, label, parent)",
          flush=True)
    weights = None
    if shape is not None:
        method, k = shape
        name = method.replace("_", "-")
        sf = dict(method=method, k=k, fixed_k=True)
        w_before = gv.shape_functions(field, before, backend=args.backend, threads=threads, **sf)
        t0 = time.perf_counter()
        w_full = gv.shape_functions(after_field, upd, backend=args.backend, threads=threads, **sf)
        t_full = time.perf_counter() - t0
        t0 = time.perf_counter()
        w_after, st = gv.update_shape_functions(w_before, before, upd, after_field, cut=cut, carved=carve,
                                                backend=backend, threads=threads, stats=True, **sf)
        t_update = time.perf_counter() - t0
        _require_same_weights(w_after, w_full)
        changed_w = ((w_before[1] != w_after[1]) | (_bits(w_before[2]) != _bits(w_after[2]))).any(axis=-1)
        weights = (w_before, w_after, changed_w.astype(np.uint8))
        full_note = " (all: no smaller set is proven)" if st["full"] else ""
        print(f"  weights update     {t_update:9.4f} s  ({name}, library update_shape_functions() on backend "
              f"{backend}; {st['recomputed']} of {st['rows']} rows recomputed{full_note}, "
              f"{int(np.count_nonzero(changed_w))} changed)")
        print(f"  weights recompute  {t_full:9.4f} s  ({name}, shape_functions() on backend {backend})  "
              f"{t_full / t_update if t_update > 0 else 0.0:.1f}x; identical bit for bit (node and weight of every "
              "slot)", flush=True)
    try:
        geometry = (spacing, origin, orientation)
        dirs = [os.path.join(args.out, sub) for sub in ("before", "after")]
        for sub in dirs:
            os.makedirs(sub, exist_ok=True)
        _write_voronoi(dirs[0], before, field, *geometry)
        _write_voronoi(dirs[1], upd, after_field, *geometry)
        gv.write_image(os.path.join(args.out, "changed.mhd"), changed, *geometry)
        if weights is not None:
            for sub, (w, idx, wt), d in zip(dirs, weights[:2], (before, upd)):
                _write_shape(sub, w, idx, wt, d.label, *geometry)
            gv.write_image(os.path.join(args.out, "changed_weights.mhd"), weights[2], *geometry)
    except OSError as e:
        raise _Failure(_strip(str(e))) from None


def _strip(message: str) -> str:
    """The API's messages start with ``geovoronoi: ``; the tool's line has its own prefix."""
    return message[len("geovoronoi: "):] if message.startswith("geovoronoi: ") else message


def _one_line(message: str) -> str:
    """Control bytes (from a file or an argument) as \\xNN, so the message stays one line and carries
    no terminal escape sequence, as the C++ tool prints them."""
    return re.sub(r"[\x00-\x1f\x7f]", lambda m: f"\\x{ord(m.group()):02x}", _strip(message))


_CUT_HELP = """\
Solves the Voronoi diagram, applies a change (cut surfaces and/or a carved box), updates the diagram
with the library's update() (only the voxels whose shortest path crossed the change are re-solved),
recomputes the changed problem from scratch on --backend, checks that both agree bit for bit
(distance, label and parent; exit 1 if not) and prints both times. With --method, the same for the
shape functions (update_shape_functions() against shape_functions() on the changed problem).
At least one --cut or a --carve is required.

--carve BOX: x0:x1,y0:y1,z0:z1, voxel indices with both ends included (0 <= x0 <= x1 < size along
x, ...); with --world, world coordinates of a closed box, taking every voxel whose centre lies in it.
Carved voxels get the field value -1 (outside); the box may hold no seed.
"""

_CUT_FILES = """\
writes, in DIR (the files of the C++ tool's cut, byte for byte, except its pictures):
  before/             the files of `voronoi` on the problem without the change
  after/              the same after the change (the updated diagram; equal to `voronoi --cut`)
  changed.mhd/.raw    1 where the distance or the label changed, else 0 (MET_UCHAR)
  with --method, also the files of `shape-functions` in before/ and after/, and
  changed_weights.mhd/.raw  1 where any slot of the voxel's weights (node or weight) changed, else 0
not written: the PNG pictures (cut.png, labels.png, distance.png, weight_node<N>.png), which the
Python API cannot draw.

example:
  python -m geovoronoi cut --stiffness stiffness.mhd --seeds seeds.csv --cut blade.obj --carve 5:6,0:9,0:2
                           --method distance-ratio --out cut-out
"""


def _parser():
    parser = _Parser(prog="python -m geovoronoi", description=__doc__.split("\n\n")[0], allow_abbrev=False)
    sub = parser.add_subparsers(dest="command")
    pv = sub.add_parser("voronoi", help="geodesic Voronoi diagram", allow_abbrev=False)
    _common(pv)
    ps = sub.add_parser("shape-functions", help="Voronoi shape functions", allow_abbrev=False)
    _common(ps)
    _add_shape_options(ps, required=True)
    pc = sub.add_parser("cut", help="a diagram before and after a cut or carving: incremental update vs full "
                        "recompute", description=_CUT_HELP, epilog=_CUT_FILES, allow_abbrev=False,
                        formatter_class=argparse.RawDescriptionHelpFormatter)
    _common(pc)
    pc.add_argument("--carve", action=_Once, metavar="BOX", help="voxels removed from the domain: x0:x1,y0:y1,z0:z1")
    _add_shape_options(pc, required=False)
    sub.add_parser("backends", help="list the backends built into the package")
    commands = {"voronoi": pv, "shape-functions": ps, "cut": pc}
    for p in commands.values():
        p.error = parser.error
    return parser, commands


def _join_values(p, args):
    """``--name value`` as ``--name=value``, so that a value starting with '-' (a negative --carve
    coordinate) is a value, as in the C++ tool; a value option with nothing after it, or followed by
    another option, is the C++ tool's 'needs a value'."""
    if "--help" in args or "-h" in args:
        return args
    out, i = [], 0
    while i < len(args):
        a = args[i]
        if not a.startswith("--"):
            raise _UsageError(f"unexpected argument '{a}'")
        if a.split("=", 1)[0] not in p._option_string_actions:
            raise _UsageError(f"unknown option '{a.split('=', 1)[0]}'")
        action = p._option_string_actions.get(a) if "=" not in a else None
        if action is not None and action.nargs != 0:
            if i + 1 >= len(args) or args[i + 1].startswith("--"):
                raise _UsageError(f"option {a} needs a value")
            out.append(f"{a}={args[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


def main(argv=None) -> int:
    parser, commands = _parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        if argv and argv[0] in commands:
            argv = [argv[0]] + _join_values(commands[argv[0]], argv[1:])
        args = parser.parse_args(argv)
        if args.command is None:
            raise _UsageError("missing command (voronoi, shape-functions, cut or backends; --help for usage)")
        if args.command == "backends":
            for b in ("seq", "thrust", "cuda"):
                print(f"{b:<7} {'built' if b in gv.backends() else 'not built'}")
            print(f"default {gv.default_backend()}")
            return 0
        start = time.perf_counter()
        if args.command == "cut":
            if not args.cut and args.carve is None:
                raise _UsageError("cut needs a change: --cut MESH and/or --carve BOX")
            if args.method is None and (args.nodes_per_voxel is not None or args.picture_node is not None):
                raise _UsageError(f"{'--nodes-per-voxel' if args.nodes_per_voxel is not None else '--picture-node'} "
                                  "needs --method (the shape functions before and after the change)")
        args.connectivity = _integer(args, "--connectivity", 26, 0, 1000)
        if args.connectivity not in (6, 18, 26):
            raise _UsageError(f"connectivity must be 6, 18 or 26, got {args.connectivity}")
        backend = gv._ext._resolve_backend(args.backend)
        threads = _threads(args, backend)
        field, spacing, origin, orientation, seeds, lines = _load(args)
        shape = _shape_args(args, len(seeds)) if getattr(args, "method", None) is not None else None
        cut = _load_cuts(args.cut, field, spacing, origin, orientation, args.connectivity)
        if args.command == "cut":
            _cut(args, field, spacing, origin, orientation, seeds, lines, cut, threads, backend, shape)
        else:
            _check_out(args.out)
            d = gv.voronoi(field, seeds, spacing=spacing, origin=origin, orientation=orientation,
                           metric=args.metric, connectivity=args.connectivity, world=args.world,
                           backend=args.backend, threads=threads, cut=cut)
            w = None
            if shape is not None:
                w = gv.shape_functions(field, d, method=shape[0], k=shape[1], backend=args.backend, threads=threads,
                                       fixed_k=True)
            try:
                os.makedirs(args.out, exist_ok=True)
                _write_voronoi(args.out, d, field, spacing, origin, orientation)
                if w is not None:
                    _write_shape(args.out, *w, d.label, spacing, origin, orientation)
            except OSError as e:
                raise _Failure(_strip(str(e))) from None
        print(f"geovoronoi {args.command}: {field.size} voxels, {len(seeds)} seeds, backend {backend}, "
              f"{time.perf_counter() - start:.2f} s, outputs in {args.out}")
        return 0
    except (_UsageError, ValueError, TypeError, OSError) as e:
        print(f"geovoronoi: error: {_one_line(str(e))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("geovoronoi: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - one line, like the C++ tool (_Failure and anything unforeseen)
        print(f"geovoronoi: failed: {_one_line(str(e))}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())

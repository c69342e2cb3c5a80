"""``python -m geovoronoi``: the command-line tool's ``voronoi`` and ``shape-functions`` commands over
the Python API.

It reads the same inputs as the C++ tool (a MetaImage stiffness volume, a CSV of seeds ``i,j,k`` in
x, y, z voxel order, or world ``x,y,z`` with ``--world``) and writes the same MetaImage, VTK and
NumPy outputs, with the same contents bit for bit. Differences from the C++ tool (docs/python.md):
no PNG pictures, no ``demo`` or ``--extrude``, only MetaImage input (``.mhd``/``.mha``), no CUDA
backend; the output folder is written in place (the C++ tool renames a finished temporary folder).
Exit codes as the C++ tool: 0 success, 2 bad input (one line on stderr), 1 anything else.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

import geovoronoi as gv


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit code 2, like the C++ tool
        raise _UsageError(message)


def _read_seeds(path: str, world: bool, shape_xyz) -> np.ndarray:
    """Rows of the seed CSV as (n, 3) x, y, z numbers (the C++ tool's format)."""
    try:
        with open(path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
    except OSError:
        raise _UsageError(f"{path}: cannot open the seed file") from None
    rows = []
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
    if not rows:
        raise _UsageError(f"{path}: no seeds in the file")
    return np.array(rows, dtype=np.float64)


def _load(args):
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
    xyz = _read_seeds(args.seeds, args.world, field.shape[::-1])
    seeds = xyz[:, ::-1]  # x, y, z -> array order z, y, x
    if not args.world:
        seeds = seeds.astype(np.int64)
    return field, tuple(spacing), tuple(origin), np.asarray(orientation, dtype=np.float64), seeds


def _common(p):
    p.add_argument("--stiffness", required=True)
    p.add_argument("--seeds", required=True)
    p.add_argument("--metric", default="min_stiffness")
    p.add_argument("--connectivity", type=int, default=26)
    p.add_argument("--backend", default="auto")
    p.add_argument("--world", action="store_true")
    p.add_argument("--cut", action="append", default=[], metavar="MESH")
    p.add_argument("--out", required=True)


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


def main(argv=None) -> int:
    parser = _Parser(prog="python -m geovoronoi", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command")
    pv = sub.add_parser("voronoi", help="geodesic Voronoi diagram")
    _common(pv)
    ps = sub.add_parser("shape-functions", help="Voronoi shape functions")
    _common(ps)
    ps.add_argument("--method", required=True)
    ps.add_argument("--nodes-per-voxel", type=int, default=4)
    sub.add_parser("backends", help="list the backends built into the package")
    for p in (pv, ps):
        p.error = parser.error
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            raise _UsageError("missing command (voronoi, shape-functions or backends; --help for usage)")
        if args.command == "backends":
            for b in ("seq", "thrust", "cuda"):
                print(f"{b:<7} {'built' if b in gv.backends() else 'not built'}")
            print(f"default {gv.default_backend()}")
            return 0
        start = time.perf_counter()
        field, spacing, origin, orientation, seeds = _load(args)
        method = None
        if args.command == "shape-functions":
            method = args.method.replace("-", "_")
            if method not in gv.METHODS:
                raise _UsageError(f"unknown method '{args.method}' (distance-ratio, sibson or laplace)")
            if not 1 <= args.nodes_per_voxel <= 64:
                raise _UsageError(f"option --nodes-per-voxel must be an integer from 1 to 64, got "
                                  f"'{args.nodes_per_voxel}'")
        cut = None
        for mesh in args.cut:  # the union of every --cut mesh, like the C++ tool
            vertices, triangles = gv.read_mesh(mesh)
            try:
                c = gv.cut_from_mesh(vertices, triangles, shape=field.shape, spacing=spacing, origin=origin,
                                     orientation=orientation, connectivity=args.connectivity)
            except ValueError as e:
                raise _UsageError(f"{mesh}: {e}") from None
            cut = c if cut is None else cut.merge(c)
        d = gv.voronoi(field, seeds, spacing=spacing, origin=origin, orientation=orientation, metric=args.metric,
                       connectivity=args.connectivity, world=args.world, backend=args.backend, cut=cut)
        if os.path.exists(args.out) and not os.path.isdir(args.out):
            raise _UsageError(f"{args.out}: exists and is not a folder")
        os.makedirs(args.out, exist_ok=True)
        _write_voronoi(args.out, d, field, spacing, origin, orientation)
        if method is not None:
            w, idx, wt = gv.shape_functions(field, d, method=method, k=args.nodes_per_voxel, backend=args.backend,
                                            fixed_k=True)
            _write_shape(args.out, w, idx, wt, d.label, spacing, origin, orientation)
        print(f"geovoronoi {args.command}: {field.size} voxels, {len(seeds)} seeds, backend "
              f"{gv._ext._resolve_backend(args.backend)}, {time.perf_counter() - start:.2f} s, outputs in {args.out}")
        return 0
    except (_UsageError, ValueError, TypeError, OSError) as e:
        print(f"geovoronoi: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("geovoronoi: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - one line, like the C++ tool
        print(f"geovoronoi: failed: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())

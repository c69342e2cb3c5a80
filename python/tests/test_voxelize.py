"""gv.voxelize: meshes to stiffness and label images, the same bit for bit as `geovoronoi voxelize`
(run by the extension, `python -m geovoronoi`, and by the C++ tool when one is built)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import geovoronoi as gv
from test_cli import CLI, needs_cli


def box(lo, hi):
    """A closed, outward-oriented box: vertices (x, y, z) and triangles."""
    v = np.array([[hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]] for i in range(8)],
                 np.float64)
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4], [2, 6, 3], [3, 6, 7], [0, 4, 2],
                  [2, 4, 6], [1, 3, 5], [3, 7, 5]], np.int64)
    return v, t


def write_obj(path, v, t):
    with open(path, "w") as f:
        for p in v:
            f.write("v %r %r %r\n" % tuple(float(x) for x in p))
        for tri in t:
            f.write("f %d %d %d\n" % tuple(int(i) + 1 for i in tri))


def write_stl(path, v, t):
    with open(path, "w") as f:
        f.write("solid s\n")
        for tri in t:
            f.write("facet normal 0 0 0\nouter loop\n")
            for i in tri:
                f.write("vertex %r %r %r\n" % tuple(float(x) for x in v[i]))
            f.write("endloop\nendfacet\n")
        f.write("endsolid s\n")


@pytest.fixture
def meshes(tmp_path):
    outer = box((0.3, 0.3, 0.3), (8.3, 6.3, 5.3))
    inner = box((2.3, 2.3, 2.3), (4.3, 4.3, 3.3))
    write_stl(tmp_path / "outer.stl", *outer)
    write_obj(tmp_path / "inner.obj", *inner)
    return tmp_path, outer, inner


def run(args, exe):
    cmd = [sys.executable, "-m", "geovoronoi"] if exe is None else [exe]
    return subprocess.run(cmd + ["voxelize"] + args, capture_output=True, text=True, timeout=300)


def test_values_labels_and_grid(meshes):
    d, outer, inner = meshes
    v = gv.voxelize([(d / "outer.stl", 2e4), (d / "inner.obj", 1.5e10, 7)], voxel_size=1.0, pad=1)
    assert v.stiffness.dtype == np.float32 and v.labels.dtype == np.int32 and v.fraction is None
    assert v.stiffness.shape == v.labels.shape and v.stiffness.ndim == 3
    counts = {int(k): int(n) for k, n in zip(*np.unique(v.labels, return_counts=True))}
    assert counts[7] == 2 * 2 * 1  # inner: 2 x 2 x 1 voxel centres
    assert counts[1] == 8 * 6 * 5 - counts[7]
    assert np.all(v.stiffness[v.labels == 1] == np.float32(2e4))
    assert np.all(v.stiffness[v.labels == 7] == np.float32(1.5e10))
    assert np.all(v.stiffness[v.labels == 0] == 0)
    assert v.stats["inside_voxels"] == counts[1] + counts[7]
    # the voxel centres of label 1 lie inside the outer box, in array-axis order (z, y, x)
    idx = np.argwhere(v.labels == 1)
    world = np.asarray(v.origin) + idx * np.asarray(v.spacing)
    assert np.all(world >= np.array([0.3, 0.3, 0.3])) and np.all(world <= np.array([5.3, 6.3, 8.3]))
    assert np.array_equal(v.orientation, np.eye(3))


def test_arrays_same_as_files(meshes):
    d, outer, inner = meshes
    from_files = gv.voxelize([(d / "outer.stl", 3.0), (d / "inner.obj", 5.0)], voxels=(10, 12, 16))
    from_arrays = gv.voxelize([((outer[0][:, ::-1], outer[1]), 3.0), ((inner[0][:, ::-1], inner[1]), 5.0)],
                              voxels=(10, 12, 16))
    assert from_files.labels.shape == (10, 12, 16)
    assert from_files.stiffness.tobytes() == from_arrays.stiffness.tobytes()
    assert from_files.labels.tobytes() == from_arrays.labels.tobytes()
    assert from_files.spacing == from_arrays.spacing and from_files.origin == from_arrays.origin


def test_dtype_fraction_and_voronoi(meshes):
    d, _, _ = meshes
    v = gv.voxelize([(d / "outer.stl", 2.0)], voxel_size=(1.0, 0.5, 1.0), fraction=2, dtype=np.float64)
    assert v.stiffness.dtype == np.float64 and v.fraction.dtype == np.float32
    assert v.fraction.shape == v.labels.shape and np.all((v.fraction >= 0) & (v.fraction <= 1))
    seeds = np.argwhere(v.labels > 0)[[0, -1]]
    diagram = gv.voronoi(v.stiffness, seeds, spacing=v.spacing, origin=v.origin, orientation=v.orientation)
    assert set(np.unique(diagram.label[v.labels > 0])) == {0, 1}


def test_errors(meshes, tmp_path):
    d, outer, _ = meshes
    with pytest.raises(ValueError, match="exactly one"):
        gv.voxelize([(d / "outer.stl", 1.0)])
    with pytest.raises(ValueError, match="exactly one"):
        gv.voxelize([(d / "outer.stl", 1.0)], voxel_size=1.0, voxels=(2, 2, 2))
    with pytest.raises(OSError, match="nope.stl"):
        gv.voxelize([(d / "nope.stl", 1.0)], voxel_size=1.0)
    with pytest.raises(ValueError, match="overlap"):
        gv.voxelize([(d / "outer.stl", 1.0)], voxel_size=1.0, overlap="middle")
    # an open box (the top face removed): refused naming an edge, accepted with winding=True
    v, t = outer
    write_obj(tmp_path / "open.obj", v, t[:-2])
    with pytest.raises(ValueError, match="edge"):
        gv.voxelize([(tmp_path / "open.obj", 1.0)], voxel_size=1.0)
    assert gv.voxelize([(tmp_path / "open.obj", 1.0)], voxel_size=1.0, winding=True).labels.any()


@pytest.mark.parametrize("exe", [None, pytest.param(CLI, marks=needs_cli)], ids=["python -m", "tool"])
def test_command_line_same_bits(meshes, exe):
    d, _, _ = meshes
    v = gv.voxelize([(d / "outer.stl", 2e4, 1), (d / "inner.obj", 1.5e10, 2)], voxel_size=(1.0, 0.5, 0.75), pad=2)
    out = d / ("out-py" if exe is None else "out-tool")
    # the command line's voxel size is x, y, z
    r = run([str(d / "outer.stl") + ":2e4:1", str(d / "inner.obj") + ":1.5e10:2", "--voxel-size", "0.75,0.5,1",
             "--pad", "2", "--format", "npy", "--out", str(out)], exe)
    assert r.returncode == 0, r.stderr
    assert "outer.stl (label 1)" in r.stdout and "mesh volume" in r.stdout
    s, lab = np.load(out / "stiffness.npy"), np.load(out / "label.npy")
    assert s.dtype == v.stiffness.dtype and s.shape == v.stiffness.shape and s.tobytes() == v.stiffness.tobytes()
    assert lab.dtype == v.labels.dtype and lab.tobytes() == v.labels.tobytes()
    grid = json.loads((out / "grid.json").read_text())
    assert tuple(grid["extents"][::-1]) == v.labels.shape
    assert tuple(grid["spacing"][::-1]) == v.spacing and tuple(grid["origin"][::-1]) == v.origin
    assert os.path.isfile(out / "labels.png")


def test_command_line_errors(meshes):
    d, _, _ = meshes
    for args, needle in [
        ([str(d / "outer.stl")], "--voxel-size"),
        ([str(d / "outer.stl"), "--voxel-size", "1", "--voxels", "2,2,2"], "not both"),
        ([str(d / "nope.stl"), "--voxel-size", "1"], "nope.stl"),
        ([str(d / "outer.stl") + ":x", "--voxel-size", "1"], ".stl or .obj"),
        ([str(d / "outer.stl") + ":1:0", "--voxel-size", "1"], "label"),
    ]:
        r = run(args + ["--out", str(d / "bad")], None)
        assert r.returncode == 2, (args, r.stderr)
        assert r.stderr.count("\n") == 1 and needle in r.stderr, r.stderr

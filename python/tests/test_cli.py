"""Bitwise equality with the C++ command-line tool on the same input, and `python -m geovoronoi`.

The C++ tool is taken from $GEOVORONOI_CLI, else from the usual build folders of this checkout;
without it the parity tests are skipped (scripts/test-python.sh runs after the C++ build)."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import geovoronoi as gv

ROOT = pathlib.Path(__file__).resolve().parents[2]


def find_cli():
    env = os.environ.get("GEOVORONOI_CLI")
    if env:
        return env if os.access(env, os.X_OK) else None
    for c in ("build/bin/geovoronoi", "build-test/bin/geovoronoi", "build/tools/geovoronoi/geovoronoi",
              "build/tools/geovoronoi", "build/examples/geovoronoi",
              "build-python/cli/examples/geovoronoi"):
        p = ROOT / c
        if p.is_file() and os.access(p, os.X_OK):
            return str(p)
    return None


CLI = find_cli()
needs_cli = pytest.mark.skipif(CLI is None, reason="C++ tool not built (set GEOVORONOI_CLI or build the tool target)")


@pytest.fixture
def job(tmp_path):
    rng = np.random.default_rng(11)
    field = rng.uniform(1.0, 50.0, (9, 12, 14)).astype(np.float32)
    field[4, 5:8, 2:9] = 0  # a masked slab
    spacing, origin = (2.0, 1.0, 0.75), (0.5, -1.0, 3.0)
    gv.write_image(tmp_path / "stiffness.mhd", field, spacing, origin)
    seeds = np.array([[0, 0, 0], [8, 11, 13], [3, 6, 7], [6, 2, 10]])  # z, y, x
    with open(tmp_path / "seeds.csv", "w") as f:
        f.write("# i,j,k\n")
        for z, y, x in seeds:
            f.write(f"{x},{y},{z}\n")
    return tmp_path, field, spacing, origin, seeds


def run_cli(args):
    r = subprocess.run([CLI] + args, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return r


def run_py(args):
    return subprocess.run([sys.executable, "-m", "geovoronoi"] + args, capture_output=True, text=True, timeout=300)


@needs_cli
@pytest.mark.parametrize("metric,conn", [("min_stiffness", 26), ("mean_cost", 6), ("uniform", 18)])
def test_voronoi_bitwise_equal_to_cli(job, metric, conn):
    tmp, field, spacing, origin, seeds = job
    run_cli(["voronoi", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"),
             "--metric", metric, "--connectivity", str(conn), "--backend", "seq", "--out", str(tmp / "cli")])
    d = gv.voronoi(field, seeds, spacing=spacing, origin=origin, metric=metric, connectivity=conn, backend="seq")
    dist, sp, org, _ = gv.read_image(tmp / "cli" / "distance.mhd")
    label, *_ = gv.read_image(tmp / "cli" / "label.mhd")
    assert sp == spacing and org == origin
    assert np.array_equal(dist.view(np.uint32), d.distance.view(np.uint32))
    assert np.array_equal(label, d.label)


@needs_cli
@pytest.mark.parametrize("method", ["distance-ratio", "laplace"])
def test_shape_functions_bitwise_equal_to_cli(job, method):
    tmp, field, spacing, origin, seeds = job
    args = ["shape-functions", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"),
            "--method", method, "--nodes-per-voxel", "3", "--backend", "seq"]
    run_cli(args + ["--out", str(tmp / "cli")])
    w, idx, wt = gv.shape_functions(field, seeds, spacing=spacing, origin=origin, method=method.replace("-", "_"),
                                    k=3, backend="seq", fixed_k=True)
    assert np.array_equal(np.load(tmp / "cli" / "weights_indptr.npy"), w.indptr)
    assert np.array_equal(np.load(tmp / "cli" / "weights_indices.npy"), w.indices)
    assert np.array_equal(np.load(tmp / "cli" / "weights_data.npy").view(np.uint32), w.data.view(np.uint32))
    cidx, *_ = gv.read_image(tmp / "cli" / "indices.mhd")  # interleaved: a K-channel image
    assert np.array_equal(cidx, np.where(idx >= 0, idx + 1, 0))
    raw = np.fromfile(tmp / "cli" / "indices_sofa_planar.raw", np.uint32)  # SOFA's planar layout
    assert np.array_equal(raw, np.moveaxis(np.where(idx >= 0, idx + 1, 0), -1, 0).ravel())
    # python -m geovoronoi writes the same files, byte for byte
    r = run_py(args + ["--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
    for name in ("distance.raw", "label.raw", "indices.raw", "weights.raw", "weights_indptr.npy",
                 "weights_indices.npy", "weights_data.npy", "distance.mhd", "label.mhd", "indices.mhd",
                 "weights.mhd", "indices_sofa_planar.mhd", "indices_sofa_planar.raw", "weights_sofa_planar.mhd",
                 "weights_sofa_planar.raw", "weights.vti", "voronoi.vti"):
        assert (tmp / "py" / name).read_bytes() == (tmp / "cli" / name).read_bytes(), name


@needs_cli
def test_world_seeds_like_cli(job):
    tmp, field, spacing, origin, seeds = job
    world = np.asarray(origin) + seeds * np.asarray(spacing) + 0.3
    with open(tmp / "world.csv", "w") as f:
        for z, y, x in world:
            f.write(f"{x!r},{y!r},{z!r}\n")
    args = ["voronoi", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "world.csv"), "--world",
            "--backend", "seq"]
    run_cli(args + ["--out", str(tmp / "cli")])
    r = run_py(args + ["--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
    for name in ("distance.raw", "label.raw"):
        assert (tmp / "py" / name).read_bytes() == (tmp / "cli" / name).read_bytes(), name


@needs_cli
@pytest.mark.parametrize("command", ["voronoi", "shape-functions"])
def test_rotated_image_like_cli(job, command):
    """A MetaImage with a TransformMatrix: world seeds go through it, every output carries it, and
    python -m geovoronoi writes the C++ tool's files byte for byte."""
    tmp, field, spacing, origin, seeds = job
    c, s_ = np.cos(0.4), np.sin(0.4)
    rot = np.array([[0.0, 0.0, 1.0], [c, -s_, 0.0], [s_, c, 0.0]])  # array-axis order, orthonormal
    gv.write_image(tmp / "rotated.mhd", field, spacing, origin, rot)
    world = np.asarray(origin) + (rot @ (seeds * np.asarray(spacing)).T).T + 0.2
    with open(tmp / "world.csv", "w") as f:
        for z, y, x in world:
            f.write(f"{x!r},{y!r},{z!r}\n")
    args = [command, "--stiffness", str(tmp / "rotated.mhd"), "--seeds", str(tmp / "world.csv"), "--world",
            "--backend", "seq"] + (["--method", "laplace", "--nodes-per-voxel", "2"] if command != "voronoi" else [])
    run_cli(args + ["--out", str(tmp / "cli")])
    r = run_py(args + ["--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
    names = ["distance.mhd", "distance.raw", "label.mhd", "label.raw", "voronoi.vti"]
    if command != "voronoi":
        names += ["indices.mhd", "weights.mhd", "weights.raw", "weights.vti", "weights_data.npy"]
    for name in names:
        assert (tmp / "py" / name).read_bytes() == (tmp / "cli" / name).read_bytes(), name
    _, _, _, o = gv.read_image(tmp / "py" / "label.mhd")
    assert np.allclose(o, rot)
    # the world seeds land on the voxels they were made from
    d = gv.voronoi(field, world, spacing=spacing, origin=origin, orientation=rot, world=True, backend="seq")
    assert np.array_equal(d.seeds, seeds)
    assert np.array_equal(d.orientation, rot)


def _blade(tmp):
    """An OBJ blade (world x, y, z, as mesh files are) cutting the job's grid partly across x."""
    path = tmp / "blade.obj"
    # x = 3 + 0.75 * 6.5 (between voxels 6 and 7), y over the first rows, z over the whole volume
    x = 3.0 + 0.75 * 6.5
    path.write_text(f"v {x} -2 -1\nv {x} 6 -1\nv {x} 6 20\nv {x} -2 20\nf 1 2 3\nf 1 3 4\n")
    return path


@pytest.mark.parametrize("command", ["voronoi", "shape-functions"])
def test_python_cli_cut_equals_the_api(job, command):
    tmp, field, spacing, origin, seeds = job
    blade = _blade(tmp)
    args = [command, "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--backend", "seq",
            "--cut", str(blade), "--cut", str(blade)] + (["--method", "sibson", "--nodes-per-voxel", "3"]
                                                       if command != "voronoi" else [])
    r = run_py(args + ["--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
    cut = gv.cut_from_mesh(*gv.read_mesh(blade), shape=field.shape, spacing=spacing, origin=origin)
    assert len(cut) > 0
    d = gv.voronoi(field, seeds, spacing=spacing, origin=origin, backend="seq", cut=cut)
    assert not np.array_equal(d.label, gv.voronoi(field, seeds, spacing=spacing, origin=origin).label)
    dist, *_ = gv.read_image(tmp / "py" / "distance.mhd")
    label, *_ = gv.read_image(tmp / "py" / "label.mhd")
    assert dist.tobytes() == d.distance.tobytes() and np.array_equal(label, d.label)
    if command != "voronoi":
        w = gv.shape_functions(field, d, method="sibson", k=3, backend="seq")
        assert np.load(tmp / "py" / "weights_data.npy").tobytes() == w.data.tobytes()


@needs_cli
@pytest.mark.parametrize("command", ["voronoi", "shape-functions"])
def test_python_cli_cut_like_cli(job, command):
    """--cut MESH: python -m geovoronoi writes the C++ tool's files byte for byte."""
    tmp, field, spacing, origin, seeds = job
    blade = _blade(tmp)
    args = [command, "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--backend", "seq",
            "--cut", str(blade)] + (["--method", "laplace", "--nodes-per-voxel", "2"] if command != "voronoi" else [])
    run_cli(args + ["--out", str(tmp / "cli")])
    r = run_py(args + ["--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
    names = ["distance.mhd", "distance.raw", "label.mhd", "label.raw", "voronoi.vti"]
    if command != "voronoi":
        names += ["indices.mhd", "weights.mhd", "weights.raw", "weights_data.npy"]
    for name in names:
        assert (tmp / "py" / name).read_bytes() == (tmp / "cli" / name).read_bytes(), name


def test_python_cli_bad_input(job):
    tmp, *_ = job
    base = ["voronoi", "--stiffness", str(tmp / "stiffness.mhd"), "--out", str(tmp / "o")]
    cases = [
        ([], "missing command"),
        (["voronoi"], "required"),
        (base + ["--seeds", str(tmp / "nope.csv")], "cannot open"),
        (["voronoi", "--stiffness", str(tmp / "x.mhd"), "--seeds", str(tmp / "seeds.csv"), "--out", str(tmp / "o")],
         "x.mhd"),
        (base + ["--seeds", str(tmp / "seeds.csv"), "--metric", "bogus"], "unknown metric"),
        (base + ["--seeds", str(tmp / "seeds.csv"), "--connectivity", "8"], "connectivity"),
    ]
    (tmp / "bad.csv").write_text("1,2,x\n")
    cases.append((base + ["--seeds", str(tmp / "bad.csv")], "bad.csv:1: 'x' is not a number"))
    (tmp / "far.csv").write_text("100,2,3\n")
    cases.append((base + ["--seeds", str(tmp / "far.csv")], "outside"))
    for args, text in cases:
        r = run_py(args)
        assert r.returncode == 2, (args, r.stderr)
        assert text in r.stderr, (args, r.stderr)
        assert len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_python_cli_backends():
    r = run_py(["backends"])
    assert r.returncode == 0 and "seq" in r.stdout and "default" in r.stdout

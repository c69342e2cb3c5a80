"""`python -m geovoronoi`: the geovoronoi command line, run by the extension (the tool's own C++ code).

Its outputs are checked against the Python API bit for bit, and once against the C++ tool's binary
byte for byte (taken from $GEOVORONOI_CLI, else from the usual build folders of this checkout; that
test is skipped without one)."""

import os
import pathlib
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import geovoronoi as gv

ROOT = pathlib.Path(__file__).resolve().parents[2]


def find_cli():
    env = os.environ.get("GEOVORONOI_CLI")
    if env:
        return env if os.access(env, os.X_OK) else None
    for c in ("build/bin/geovoronoi", "build-test/bin/geovoronoi"):
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


def run_py(args, **kwargs):
    return subprocess.run([sys.executable, "-m", "geovoronoi"] + args, capture_output=True, text=True, timeout=300,
                          **kwargs)


def run_ok(args):
    r = run_py(args)
    assert r.returncode == 0, r.stderr
    return r


def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


def _untimed(text, out=None):
    """The printed lines with every time (and the output folder) replaced by a placeholder."""
    if out is not None:
        text = text.replace(str(out), "OUT")
    return [re.sub(r"\d+\.\d+( ?s|x)", r"T\1", line) for line in text.splitlines()]


# ---- the same outputs as the Python API -------------------------------------------------------------

@pytest.mark.parametrize("metric,conn", [("min_stiffness", 26), ("mean_cost", 6), ("uniform", 18)])
def test_voronoi_bitwise_equal_to_the_api(job, metric, conn):
    tmp, field, spacing, origin, seeds = job
    run_ok(["voronoi", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"),
            "--metric", metric, "--connectivity", str(conn), "--backend", "seq", "--out", str(tmp / "cli")])
    d = gv.voronoi(field, seeds, spacing=spacing, origin=origin, metric=metric, connectivity=conn, backend="seq")
    dist, sp, org, _ = gv.read_image(tmp / "cli" / "distance.mhd")
    label, *_ = gv.read_image(tmp / "cli" / "label.mhd")
    assert sp == spacing and org == origin
    assert np.array_equal(dist.view(np.uint32), d.distance.view(np.uint32))
    assert np.array_equal(label, d.label)


@pytest.mark.parametrize("method", ["distance-ratio", "laplace"])
def test_shape_functions_bitwise_equal_to_the_api(job, method):
    tmp, field, spacing, origin, seeds = job
    run_ok(["shape-functions", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"),
            "--method", method, "--nodes-per-voxel", "3", "--backend", "seq", "--out", str(tmp / "cli")])
    w, idx, wt = gv.shape_functions(field, seeds, spacing=spacing, origin=origin, method=method.replace("-", "_"),
                                    k=3, backend="seq", fixed_k=True)
    assert np.array_equal(np.load(tmp / "cli" / "weights_indptr.npy"), w.indptr)
    assert np.array_equal(np.load(tmp / "cli" / "weights_indices.npy"), w.indices)
    assert np.array_equal(np.load(tmp / "cli" / "weights_data.npy").view(np.uint32), w.data.view(np.uint32))
    cidx, *_ = gv.read_image(tmp / "cli" / "indices.mhd")  # interleaved: a K-channel image
    assert np.array_equal(cidx, np.where(idx >= 0, idx + 1, 0))
    raw = np.fromfile(tmp / "cli" / "indices_sofa_planar.raw", np.uint32)  # SOFA's planar layout
    assert np.array_equal(raw, np.moveaxis(np.where(idx >= 0, idx + 1, 0), -1, 0).ravel())


@pytest.mark.parametrize("command", ["voronoi", "shape-functions"])
def test_rotated_image_like_the_api(job, command):
    """A MetaImage with a TransformMatrix: world seeds go through it as the API's world=True does, and
    every output carries it."""
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
    run_ok(args + ["--out", str(tmp / "py")])
    d = gv.voronoi(field, world, spacing=spacing, origin=origin, orientation=rot, world=True, backend="seq")
    assert np.array_equal(d.seeds, seeds)  # the world seeds land on the voxels they were made from
    dist, _, _, o = gv.read_image(tmp / "py" / "distance.mhd")
    label, *_ = gv.read_image(tmp / "py" / "label.mhd")
    assert np.allclose(o, rot)
    assert dist.tobytes() == d.distance.tobytes() and np.array_equal(label, d.label)
    if command != "voronoi":
        w = gv.shape_functions(field, d, method="laplace", k=2, backend="seq")
        assert np.load(tmp / "py" / "weights_data.npy").tobytes() == w.data.tobytes()


def _blade(tmp):
    """An OBJ blade (world x, y, z, as mesh files are) cutting the job's grid partly across x."""
    path = tmp / "blade.obj"
    # x = 3 + 0.75 * 6.5 (between voxels 6 and 7), y over the first rows, z over the whole volume
    x = 3.0 + 0.75 * 6.5
    path.write_text(f"v {x} -2 -1\nv {x} 6 -1\nv {x} 6 20\nv {x} -2 20\nf 1 2 3\nf 1 3 4\n")
    return path


@pytest.mark.parametrize("command", ["voronoi", "shape-functions"])
def test_cut_option_equals_the_api(job, command):
    tmp, field, spacing, origin, seeds = job
    blade = _blade(tmp)
    args = [command, "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--backend", "seq",
            "--cut", str(blade), "--cut", str(blade)] + (["--method", "sibson", "--nodes-per-voxel", "3"]
                                                       if command != "voronoi" else [])
    run_ok(args + ["--out", str(tmp / "py")])
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


_BOX = "2:4,8:11,0:8"  # voxels x 2..4, y 8..11, z 0..8 of the job's grid, away from every seed
_WORLD_BOX = "4.5:6.0,7.0:10.0,0.5:16.5"  # the same box in world coordinates (ends on voxel centres)


def test_cut_equals_the_api(job):
    """before/ is voronoi without the change, after/ voronoi with the cut on the carved field (carved
    voxels -1), changed.mhd marks exactly the voxels that differ, and the shape functions are the API's."""
    tmp, field, spacing, origin, seeds = job
    blade = _blade(tmp)
    r = run_ok(["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--cut",
                str(blade), "--carve", _BOX, "--method", "laplace", "--nodes-per-voxel", "3", "--backend", "seq",
                "--out", str(tmp / "py")])
    cut = gv.cut_from_mesh(*gv.read_mesh(blade), shape=field.shape, spacing=spacing, origin=origin)
    carved = field.copy()
    carved[0:9, 8:12, 2:5] = -1
    before = gv.voronoi(field, seeds, spacing=spacing, origin=origin, backend="seq")
    after = gv.voronoi(carved, seeds, spacing=spacing, origin=origin, backend="seq", cut=cut)
    for sub, d, f in (("before", before, field), ("after", after, carved)):
        dist, *_ = gv.read_image(tmp / "py" / sub / "distance.mhd")
        label, *_ = gv.read_image(tmp / "py" / sub / "label.mhd")
        assert dist.tobytes() == d.distance.tobytes() and np.array_equal(label, d.label), sub
        w = gv.shape_functions(f, d, method="laplace", k=3, backend="seq")
        assert np.load(tmp / "py" / sub / "weights_data.npy").tobytes() == w.data.tobytes(), sub
    changed, *_ = gv.read_image(tmp / "py" / "changed.mhd")
    assert changed.dtype == np.uint8
    assert np.array_equal(changed, ((before.distance != after.distance) | (before.label != after.label)))
    assert changed[0:9, 8:12, 2:5].all()  # the carved voxels left the domain
    assert re.search(r"weights update +\d+\.\d{4} s +\(laplace, library update_shape_functions\(\) on backend seq; "
                     r"\d+ of 1512 rows recomputed, \d+ changed\)", r.stdout), r.stdout


def test_cut_world_box_is_the_index_box(job):
    """--world --carve with ends exactly on voxel centres takes the voxels of the same index box."""
    tmp, field, spacing, origin, seeds = job
    world = tmp / "world.csv"
    with open(world, "w") as f:
        for z, y, x in np.asarray(origin) + seeds * np.asarray(spacing):
            f.write(f"{x!r},{y!r},{z!r}\n")
    base = ["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--backend", "seq"]
    run_ok(base + ["--seeds", str(tmp / "seeds.csv"), "--carve", _BOX, "--out", str(tmp / "a")])
    r = run_ok(base + ["--seeds", str(world), "--world", "--carve", _WORLD_BOX, "--out", str(tmp / "b")])
    assert " 108 carved voxels" in r.stdout  # 3 x 4 x 9
    for name in ("after/distance.raw", "after/label.raw", "changed.raw"):
        assert (tmp / "a" / name).read_bytes() == (tmp / "b" / name).read_bytes(), name


@pytest.mark.skipif("thrust" not in gv.backends(), reason="thrust backend not built")
def test_threads_option(job):
    """--threads N runs the thrust backend on N threads, bit for bit what seq gives; a bad N exits 2."""
    tmp, *_ = job
    base = ["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--carve", _BOX,
            "--method", "distance-ratio"]
    r = run_ok(base + ["--backend", "thrust", "--threads", "2", "--out", str(tmp / "t")])
    assert "backend thrust" in r.stdout
    run_ok(base + ["--backend", "seq", "--threads", "2", "--out", str(tmp / "s")])
    for name in ("after/distance.raw", "after/label.raw", "after/weights.raw", "changed_weights.raw"):
        assert (tmp / "t" / name).read_bytes() == (tmp / "s" / name).read_bytes(), name
    r = run_py(base + ["--threads", "0", "--out", str(tmp / "bad")])
    assert r.returncode == 2 and "option --threads must be an integer from 1 to" in r.stderr, r.stderr


# ---- the same bytes as the C++ tool -----------------------------------------------------------------

@needs_cli
def test_same_bytes_as_the_tool(job):
    """python -m geovoronoi and the tool's binary run the same code: every file (pictures and the
    output folder's marker included), the printed lines but for the times, and the exit codes."""
    tmp, *_ = job
    blade = str(_blade(tmp))
    base = ["--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--backend", "seq"]
    runs = {
        "voronoi": ["voronoi"] + base + ["--precision", "double"],
        "sibson": ["shape-functions"] + base + ["--method", "sibson", "--nodes-per-voxel", "3", "--cut", blade],
        "cut": ["cut"] + base + ["--cut", blade, "--carve", _BOX, "--method", "laplace"],
        "bad": ["voronoi"] + base + ["--metric", "bogus"],
    }
    (tmp / "cli").mkdir()
    (tmp / "py").mkdir()
    for name, args in runs.items():
        cli = subprocess.run([CLI] + args + ["--out", str(tmp / "cli" / name)], capture_output=True, text=True,
                             timeout=300)
        py = run_py(args + ["--out", str(tmp / "py" / name)])
        assert py.returncode == cli.returncode == (2 if name == "bad" else 0), (name, cli.stderr, py.stderr)
        assert py.stderr == cli.stderr, name
        assert _untimed(py.stdout, tmp / "py") == _untimed(cli.stdout, tmp / "cli"), name
        if name == "bad":
            continue
        files = _files(tmp / "cli" / name)
        assert _files(tmp / "py" / name) == files and any(f.endswith(".png") for f in files)
        for f in files:
            assert (tmp / "py" / name / f).read_bytes() == (tmp / "cli" / name / f).read_bytes(), (name, f)
    # (not `backends`: the tool may have the cuda backend, which the package never has)
    for args in (["--help"], ["--version"], ["cut", "--help"]):
        cli = subprocess.run([CLI] + args, capture_output=True, text=True, timeout=60)
        py = run_py(args)
        assert (py.returncode, py.stdout, py.stderr) == (cli.returncode, cli.stdout, cli.stderr), args


# ---- the command line's contract ------------------------------------------------------------------

def test_help_and_version():
    r = run_py(["--help"])
    assert r.returncode == 0 and r.stderr == ""
    for needle in ("usage: geovoronoi COMMAND", "voronoi", "shape-functions", "cut", "demo", "backends", "exit codes"):
        assert needle in r.stdout, needle
    r = run_py(["cut", "--help"])
    assert r.returncode == 0
    for needle in ("--carve BOX", "x0:x1,y0:y1,z0:z1", "changed.mhd", "changed_weights.mhd", "--method", "example:"):
        assert needle in r.stdout, needle
    r = run_py(["--version"])
    assert r.returncode == 0 and re.fullmatch(r"geovoronoi \d+\.\d+\.\d+\n", r.stdout), r.stdout


def test_backends():
    r = run_py(["backends"])
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("seq     built, sequential Dijkstra")
    assert lines[-1] == "default " + gv.default_backend()


def test_bad_input_exits_2_with_one_line(job):
    tmp, *_ = job
    base = ["voronoi", "--stiffness", str(tmp / "stiffness.mhd"), "--out", str(tmp / "o")]
    (tmp / "bad.csv").write_text("1,2,x\n")
    (tmp / "far.csv").write_text("100,2,3\n")
    cases = [
        ([], "missing command"),
        (["frobnicate"], "unknown command 'frobnicate'"),
        (["voronoi"], "missing required option --stiffness"),
        (base + ["--seeds", str(tmp / "nope.csv")], "nope.csv"),
        (["voronoi", "--stiffness", str(tmp / "x.mhd"), "--seeds", str(tmp / "seeds.csv"), "--out", str(tmp / "o")],
         "x.mhd"),
        (base + ["--seeds", str(tmp / "seeds.csv"), "--metric", "bogus"], "unknown metric 'bogus'"),
        (base + ["--seeds", str(tmp / "seeds.csv"), "--connectivity", "8"], "connectivity must be 6, 18 or 26, got 8"),
        (base + ["--seeds", str(tmp / "seeds.csv"), "--backend", "gpu"], "unknown backend 'gpu'"),
        (base + ["--seeds", str(tmp / "bad.csv")], "bad.csv:1: 'x' is not a number"),
        (base + ["--seeds", str(tmp / "far.csv")], "outside"),
        (["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--carve", "4:2,8:11,0:8",
          "--out", str(tmp / "o")], "the x range runs backwards"),
    ]
    for args, text in cases:
        r = run_py(args)
        assert r.returncode == 2, (args, r.stderr)
        assert r.stderr.startswith("geovoronoi: error: ") and text in r.stderr, (args, r.stderr)
        assert len(r.stderr.splitlines()) == 1 and r.stdout == "", (args, r.stderr)
    assert not (tmp / "o").exists()


def _slow_job(tmp_path):
    """A shape-functions run of a few seconds on one thread: (arguments without --out)."""
    rng = np.random.default_rng(3)
    field = rng.uniform(1.0, 50.0, (24, 40, 40)).astype(np.float32)
    gv.write_image(tmp_path / "stiffness.mhd", field)
    with open(tmp_path / "seeds.csv", "w") as f:
        for i in range(8):
            f.write(f"{4 * i + 1},{3 * i + 2},{2 * i + 1}\n")
    return ["shape-functions", "--stiffness", str(tmp_path / "stiffness.mhd"), "--seeds", str(tmp_path / "seeds.csv"),
            "--method", "laplace", "--backend", "seq"]


def _start_and_wait_for_partial(args, tmp_path):
    """Starts python -m geovoronoi ARGS --out tmp_path/o and returns once its partial folder exists."""
    p = subprocess.Popen([sys.executable, "-m", "geovoronoi"] + args + ["--out", str(tmp_path / "o")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(tmp_path.glob("o.partial-*")) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert p.poll() is None, "the run ended before its output folder could be touched"
    return p


def test_runtime_failure_exits_1(tmp_path):
    """A failure that is not the input's (here: another run created the output folder while this one
    was computing) exits 1 with one line, as the tool does."""
    p = _start_and_wait_for_partial(_slow_job(tmp_path), tmp_path)
    (tmp_path / "o").mkdir()
    out, err = p.communicate(timeout=300)
    assert p.returncode == 1, err
    # one line for the failure (a slow machine may print progress lines before it, never another error)
    lines = err.splitlines()
    assert lines[-1].startswith("geovoronoi: failed: ") and "another run replaced this folder" in lines[-1], err
    assert not any(line.startswith("geovoronoi: ") for line in lines[:-1]) and out == "", err
    assert not list(tmp_path.glob("o.partial-*")) and not any((tmp_path / "o").iterdir())


def test_output_order_with_python_prints(tmp_path):
    """What the command line prints comes out where the call is, between Python's own prints."""
    code = ("import sys\nfrom geovoronoi.__main__ import main\nprint('before')\nrc = main(['--version'])\n"
            "print('after', rc)\nsys.exit(main(['--metric']))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert re.fullmatch(r"before\ngeovoronoi \d+\.\d+\.\d+\nafter 0\n", r.stdout), r.stdout
    assert r.stderr.startswith("geovoronoi: error: unknown command '--metric'"), r.stderr


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_ctrl_c_ends_the_run_as_the_tool(tmp_path):
    """SIGINT (Ctrl-C) during a run removes its partial output folder and ends the process by the
    signal, as it ends the tool; the folder given to --out is left as it was (absent)."""
    p = _start_and_wait_for_partial(_slow_job(tmp_path), tmp_path)
    time.sleep(0.2)
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=60)
    assert p.returncode == -signal.SIGINT
    assert not list(tmp_path.glob("o.partial-*")) and not (tmp_path / "o").exists()

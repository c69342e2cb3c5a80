"""Bitwise equality with the C++ command-line tool on the same input, and `python -m geovoronoi`.

The C++ tool is taken from $GEOVORONOI_CLI, else from the usual build folders of this checkout;
without it the parity tests are skipped (scripts/test-python.sh runs after the C++ build)."""

import os
import re
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


# ---- cut: python -m geovoronoi cut against the C++ tool's cut ----------------------------------------

# what the C++ tool's cut writes that python -m geovoronoi does not: its pictures and the marker of
# its replaced-as-a-whole output folder (docs/python.md)
_NOT_WRITTEN = (".png", ".geovoronoi-output")
# a box of voxels x 2..4, y 8..11, z 0..8 of the job's grid, away from every seed, in voxel indices
# and in world coordinates whose ends are exactly voxel centres (origin + index * spacing; ends included)
_BOX = "2:4,8:11,0:8"
_WORLD_BOX = "4.5:6.0,7.0:10.0,0.5:16.5"


def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


def _world_seeds(tmp, seeds, origin, spacing, rot=None, name="world.csv"):
    """The seeds' voxel centres as a CSV of world x, y, z (through the direction matrix @p rot)."""
    step = seeds * np.asarray(spacing)
    world = np.asarray(origin) + (step if rot is None else (rot @ step.T).T)
    path = tmp / name
    with open(path, "w") as f:
        for z, y, x in world:
            f.write(f"{x!r},{y!r},{z!r}\n")
    return path


def _cut_cases(tmp, field, spacing, origin, seeds):
    blade = str(_blade(tmp))
    c, s_ = np.cos(0.4), np.sin(0.4)
    rot = np.array([[0.0, 0.0, 1.0], [c, -s_, 0.0], [s_, c, 0.0]])
    gv.write_image(tmp / "rotated.mhd", field, spacing, origin, rot)
    plain = ["--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv")]
    world = ["--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(_world_seeds(tmp, seeds, origin, spacing)),
             "--world"]
    rotated = ["--stiffness", str(tmp / "rotated.mhd"), "--seeds",
               str(_world_seeds(tmp, seeds, origin, spacing, rot, "rotated.csv")), "--world"]
    return {
        "mesh": plain + ["--cut", blade],
        "carve": plain + ["--carve", _BOX, "--connectivity", "6"],
        "world-carve": world + ["--carve", _WORLD_BOX, "--cut", blade],
        # a rotated grid: the world box takes the voxels whose centre (through the matrix) lies in it
        "rotated-carve": rotated + ["--carve", "12.5:16,1:5,0:5"],
        "sibson": plain + ["--cut", blade, "--carve", _BOX, "--method", "sibson", "--nodes-per-voxel", "2"],
        "distance-ratio": plain + ["--cut", blade, "--method", "distance-ratio", "--metric", "mean_stiffness"],
    }


_CUT_CASES = ["mesh", "carve", "world-carve", "rotated-carve", "sibson", "distance-ratio"]


@needs_cli
@pytest.mark.parametrize("case", _CUT_CASES)
def test_cut_like_cli(job, case):
    """python -m geovoronoi cut writes the C++ tool's cut files byte for byte (all but the pictures),
    and prints the same counts in the same lines."""
    tmp, field, spacing, origin, seeds = job
    args = ["cut"] + _cut_cases(tmp, field, spacing, origin, seeds)[case] + ["--backend", "seq"]
    cli = run_cli(args + ["--out", str(tmp / "cli")])
    py = run_py(args + ["--out", str(tmp / "py")])
    assert py.returncode == 0, py.stderr
    assert py.stderr == ""
    want = [f for f in _files(tmp / "cli") if not f.endswith(_NOT_WRITTEN)]
    assert _files(tmp / "py") == want
    assert "before/distance.raw" in want and "changed.raw" in want
    assert ("changed_weights.raw" in want) == ("--method" in args)
    for name in want:
        assert (tmp / "py" / name).read_bytes() == (tmp / "cli" / name).read_bytes(), name
    # the change changed something, and the mask says where
    changed = np.fromfile(tmp / "py" / "changed.raw", np.uint8)
    assert changed.any()
    # the printed lines: the same text but for the times
    def untimed(text):
        return [re.sub(r"\d+\.\d+(x| s)", r"T\1", line) for line in text.splitlines()]
    cl, pl = untimed(cli.stdout), untimed(py.stdout)
    assert len(pl) == len(cl) == (6 if "--method" in args else 4)
    assert pl[:-1] == cl[:-1]
    assert re.fullmatch(r"geovoronoi cut: 1512 voxels, 4 seeds, backend seq, T s, outputs in .*", pl[-1])


def test_cut_equals_the_api(job):
    """Without the C++ tool: before/ is voronoi without the change, after/ voronoi with the cut on the
    carved field (carved voxels -1), changed.mhd marks exactly the voxels that differ, and the shape
    functions are the API's."""
    tmp, field, spacing, origin, seeds = job
    blade = _blade(tmp)
    r = run_py(["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--cut",
                str(blade), "--carve", _BOX, "--method", "laplace", "--nodes-per-voxel", "3", "--backend", "seq",
                "--out", str(tmp / "py")])
    assert r.returncode == 0, r.stderr
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
    cw, *_ = gv.read_image(tmp / "py" / "changed_weights.mhd")
    differ = np.zeros(field.shape, bool)
    for name in ("weights.mhd", "indices.mhd"):  # a slot's node or weight
        b, *_ = gv.read_image(tmp / "py" / "before" / name)
        a, *_ = gv.read_image(tmp / "py" / "after" / name)
        differ |= (b != a).any(axis=-1)
    assert np.array_equal(cw, differ) and cw.any()
    assert re.search(r"weights update +\d+\.\d{4} s +\(laplace, library update_shape_functions\(\) on backend [a-z() ]+; \d+ of "
                     r"1512 rows recomputed, \d+ changed\)", r.stdout), r.stdout


def test_cut_world_box_is_the_index_box(job):
    """--world --carve with ends exactly on voxel centres takes the voxels of the same index box."""
    tmp, field, spacing, origin, seeds = job
    world = _world_seeds(tmp, seeds, origin, spacing)
    base = ["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--backend", "seq"]
    assert run_py(base + ["--seeds", str(tmp / "seeds.csv"), "--carve", _BOX, "--out", str(tmp / "a")]).returncode == 0
    r = run_py(base + ["--seeds", str(world), "--world", "--carve", _WORLD_BOX, "--out", str(tmp / "b")])
    assert r.returncode == 0, r.stderr
    assert " 108 carved voxels" in r.stdout  # 3 x 4 x 9
    for name in ("after/distance.raw", "after/label.raw", "changed.raw"):
        assert (tmp / "a" / name).read_bytes() == (tmp / "b" / name).read_bytes(), name


def test_cut_bad_input(job):
    """Bad input: exit 2 and one line, the C++ tool's line where it has the same check, nothing written."""
    tmp, *_ = job
    blade = str(_blade(tmp))
    (tmp / "bad.obj").write_text("v 1 2 3\nf 1 2 7\n")
    (tmp / "blade.txt").write_text("")
    base = ["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--backend", "seq"]
    cases = [
        ([], "cut needs a change: --cut MESH and/or --carve BOX"),
        (["--cut", str(tmp / "nowhere.stl")], "nowhere.stl"),
        (["--cut", str(tmp / "bad.obj")], "bad.obj"),
        (["--cut", str(tmp / "blade.txt")], "--cut takes a .stl or .obj mesh"),
        (["--carve", "2:4,8:11"], "expected three ranges x0:x1,y0:y1,z0:z1"),
        (["--carve", "2:4,8:12,0:8"], "the y range leaves the grid (indices 0 to 11)"),
        (["--carve", "-1:4,8:11,0:8"], "the x range leaves the grid"),
        (["--carve", "4:2,8:11,0:8"], "the x range runs backwards"),
        (["--carve", "2:a,8:11,0:8"], "'a' in the x range is not a voxel index"),
        (["--carve", "2.5:4,8:11,0:8"], "'2.5' in the x range is not a voxel index"),
        (["--carve", "2,8:11,0:8"], "the x range '2' is not FROM:TO"),
        (["--carve", "0:1,0:1,0:1"], "removes the seed on line 2 of"),
        (["--carve", "4.6:4.7,7:10,0:17", "--world"], "the box holds no voxel centre of the grid"),
        (["--carve", "4.6:nan,7:10,0:17", "--world"], "'nan' in the x range is not a finite number"),
        (["--carve", _BOX, "--carve", _BOX], "option --carve given twice"),
        (["--cut", blade, "--method", "voronoi"], "unknown method 'voronoi' (distance-ratio, sibson or laplace)"),
        (["--cut", blade, "--method", "sibson", "--nodes-per-voxel", "0"],
         "option --nodes-per-voxel must be an integer from 1 to 64, got '0'"),
        (["--cut", blade, "--nodes-per-voxel", "3"], "--nodes-per-voxel needs --method"),
        (["--cut", blade, "--method", "sibson", "--picture-node", "4"],
         "--picture-node 4: must be less than the number of nodes (4)"),
        (["--cut", blade, "--method"], "option --method needs a value"),
        (["--cut", blade, "--bogus", "1"], "unknown option '--bogus'"),
        (["--cut", blade, "--connectivity", "8"], "connectivity must be 6, 18 or 26, got 8"),
    ]
    for i, (extra, text) in enumerate(cases):
        out = tmp / f"bad{i}"
        args = base + extra + ["--out", str(out)]
        r = run_py(args)
        assert r.returncode == 2, (extra, r.stderr)
        assert r.stderr.startswith("geovoronoi: error: ") and text in r.stderr, (extra, r.stderr)
        assert len(r.stderr.splitlines()) == 1 and r.stdout == "", (extra, r.stderr)
        assert not out.exists(), extra
        if CLI is not None:  # the C++ tool says the same (its mesh reader's text aside, which is the library's)
            c = subprocess.run([CLI] + args, capture_output=True, text=True, timeout=60)
            assert c.returncode == 2, (extra, c.stderr)
            assert c.stderr == r.stderr, (extra, c.stderr, r.stderr)


def test_cut_mismatch_exits_1(job, monkeypatch, capsys):
    """If the update ever differed from the full recompute (a library bug), the run fails with exit 1
    and one line, and writes nothing. Simulated by an update that returns the diagram unchanged."""
    import geovoronoi.__main__ as cli

    tmp, *_ = job
    def no_update(d, *args, **kwargs):
        d.stats = {"invalidated": 0}
        return d

    monkeypatch.setattr(gv, "update", no_update)
    rc = cli.main(["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"),
                   "--carve", _BOX, "--backend", "seq", "--out", str(tmp / "o")])
    err = capsys.readouterr().err
    assert rc == 1
    assert err.startswith("geovoronoi: failed: internal error: the incremental update differs from the full "
                          "recompute in its distance at voxel (") and len(err.splitlines()) == 1, err
    assert not (tmp / "o").exists()


def test_cut_help():
    r = run_py(["cut", "--help"])
    assert r.returncode == 0
    for needle in ("--carve BOX", "x0:x1,y0:y1,z0:z1", "changed.mhd", "changed_weights.mhd", "--method",
                   "not written: the PNG pictures", "example:"):
        assert needle in r.stdout, needle


@pytest.mark.skipif("thrust" not in gv.backends(), reason="thrust backend not built")
def test_threads_option(job):
    """--threads N runs the thrust backend on N threads, bit for bit what seq gives; a bad N exits 2."""
    tmp, *_ = job
    base = ["cut", "--stiffness", str(tmp / "stiffness.mhd"), "--seeds", str(tmp / "seeds.csv"), "--carve", _BOX,
            "--method", "distance-ratio"]
    r = run_py(base + ["--backend", "thrust", "--threads", "2", "--out", str(tmp / "t")])
    assert r.returncode == 0 and "backend thrust" in r.stdout, r.stderr
    assert run_py(base + ["--backend", "seq", "--threads", "2", "--out", str(tmp / "s")]).returncode == 0
    for name in ("after/distance.raw", "after/label.raw", "after/weights.raw", "changed_weights.raw"):
        assert (tmp / "t" / name).read_bytes() == (tmp / "s" / name).read_bytes(), name
    r = run_py(base + ["--threads", "0", "--out", str(tmp / "bad")])
    assert r.returncode == 2 and "option --threads must be an integer from 1 to" in r.stderr, r.stderr

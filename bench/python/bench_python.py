#!/usr/bin/env python3
"""Python-package benchmarks (docs/benchmarks.md, "Python package"):

1. binding overhead: geovoronoi.voronoi() from Python against the C++ entry point it calls
   (geovoronoi::voronoi, timed inside the extension around the library call alone), 128^3 gradient,
   10 seeds, min_stiffness, 26-connectivity; median of --repeat runs per backend;
2. against scikit-image's MCP_Geometric (mean_cost metric, 26 neighbours: the same graph problem) and
   SciPy's csgraph.dijkstra(min_only=True) (min_stiffness graph, 26 neighbours), in the same run;
3. the GIL released: two seq solves in two Python threads against the same two solves in turn (wall
   time ratio, best and median of --repeat; process CPU over wall shows the overlap). This is the
   timing half of test_threads.py's side-by-side test, which checks the results bit for bit and
   asserts no time: timing belongs here, on a quiet machine, not in a unit test.

Usage: python bench/python/bench_python.py [--n 128] [--repeat 5] [--skip-baselines] [--skip-threads]
(with the package installed, e.g. build-python/venv/bin/python after scripts/test-python.sh).
"""

import argparse
import itertools
import os
import statistics
import threading
import time

import numpy as np

import geovoronoi as gv
from geovoronoi import _geovoronoi as ext


def gradient(n):
    # phantom::gradient: 1 -> 10 along x (the last array axis), float32
    x = np.arange(n, dtype=np.float64)
    row = (1.0 + 9.0 * x / max(n - 1, 1)).astype(np.float32)
    return np.ascontiguousarray(np.broadcast_to(row, (n, n, n)))


def seeds_for(n, k=10):
    rng = np.random.default_rng(2016)
    return np.unique(rng.integers(0, n, (k, 3)), axis=0)


def csgraph_problem(field, metric="min_stiffness"):
    import scipy.sparse

    shape, n = field.shape, field.size
    idx = np.arange(n).reshape(shape)
    rows, cols, vals = [], [], []
    f = field.astype(np.float64)
    for off in itertools.product((-1, 0, 1), repeat=3):
        if off == (0, 0, 0):
            continue
        src = tuple(slice(max(0, -o), s - max(0, o)) for o, s in zip(off, shape))
        dst = tuple(slice(max(0, o), s - max(0, -o)) for o, s in zip(off, shape))
        length = float(np.sqrt(np.sum(np.square(off))))
        rows.append(idx[src].ravel())
        cols.append(idx[dst].ravel())
        vals.append((length / np.minimum(f[src], f[dst])).ravel())
    return scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def two_threads(field, seeds, repeat):
    print("\n## two seq solves: two Python threads against one after the other (wall time), repeat", repeat)

    def one():
        gv.voronoi(field, seeds, backend="seq")

    ratios, loads = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        one()
        one()
        serial = time.perf_counter() - t0
        threads = [threading.Thread(target=one) for _ in range(2)]
        t0, c0 = time.perf_counter(), time.process_time()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        ratios.append(wall / serial)
        loads.append(cpu / wall)
        print(f"in turn {serial:.3f} s, two threads {wall:.3f} s: ratio {wall / serial:.2f}, CPU/wall {cpu / wall:.2f}")
    print(f"two threads / in turn: best {min(ratios):.2f}, median {statistics.median(ratios):.2f} "
          f"(1.0 = no overlap, 0.5 = perfect on two cores); load average now {os.getloadavg()[0]:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=128)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--skip-baselines", action="store_true")
    ap.add_argument("--skip-threads", action="store_true")
    a = ap.parse_args()
    field, seeds = gradient(a.n), seeds_for(a.n)
    print(f"# {a.n}^3 gradient, {len(seeds)} seeds, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
          f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs, backends {gv.backends()}")

    print("\n## binding overhead (min_stiffness, 26 neighbours): median of", a.repeat)
    for backend in gv.backends():
        py, core = [], []
        for _ in range(a.repeat):
            t0 = time.perf_counter()
            d = gv.voronoi(field, seeds, backend=backend)
            py.append(time.perf_counter() - t0)
            core.append(ext._last_core_seconds())
            del d
        mp, mc = statistics.median(py), statistics.median(core)
        over = [(p - c) / c for p, c in zip(py, core)]
        print(f"{backend:7s} python {mp:.3f} s  C++ call {mc:.3f} s  overhead median {100 * statistics.median(over):.2f} %"
              f"  (max {100 * max(over):.2f} %, absolute {1000 * statistics.median([p - c for p, c in zip(py, core)]):.2f} ms)")

    if not a.skip_threads:
        two_threads(field, seeds, a.repeat)
    if a.skip_baselines:
        return
    print("\n## against scikit-image MCP_Geometric and SciPy csgraph.dijkstra (one run each)")
    from skimage.graph import MCP_Geometric
    import scipy.sparse.csgraph

    times = {}
    for backend in gv.backends():
        t0 = time.perf_counter()
        gv.voronoi(field, seeds, metric="mean_cost", backend=backend)
        times[f"geovoronoi {backend} mean_cost"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        gv.voronoi(field, seeds, metric="min_stiffness", backend=backend)
        times[f"geovoronoi {backend} min_stiffness"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    mcp = MCP_Geometric(field.astype(np.float64), fully_connected=True)
    cum, _ = mcp.find_costs([tuple(s) for s in seeds])
    times["MCP_Geometric (mean_cost)"] = time.perf_counter() - t0
    d = gv.voronoi(field.astype(np.float64), seeds, metric="mean_cost", backend="seq")
    print(f"MCP_Geometric agrees: max relative distance difference "
          f"{np.max(np.abs(d.distance - cum) / np.maximum(cum, 1e-300)):.2e}")
    t0 = time.perf_counter()
    graph = csgraph_problem(field)
    times["csgraph graph build"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    dist, _, src = scipy.sparse.csgraph.dijkstra(graph, indices=np.ravel_multi_index(tuple(seeds.T), field.shape),
                                                 min_only=True, return_predecessors=True)
    times["csgraph dijkstra (min_stiffness)"] = time.perf_counter() - t0
    del graph
    for k, v in times.items():
        print(f"{k:36s} {v:8.3f} s")
    for backend in gv.backends():
        print(f"speed-up of {backend}: MCP_Geometric / geovoronoi {times['MCP_Geometric (mean_cost)'] / times[f'geovoronoi {backend} mean_cost']:.1f}x, "
              f"csgraph dijkstra / geovoronoi {times['csgraph dijkstra (min_stiffness)'] / times[f'geovoronoi {backend} min_stiffness']:.1f}x "
              f"(with graph build {(times['csgraph dijkstra (min_stiffness)'] + times['csgraph graph build']) / times[f'geovoronoi {backend} min_stiffness']:.1f}x)")
    print(f"load average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()

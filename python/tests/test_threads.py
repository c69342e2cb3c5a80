"""The GIL is released during solves, progress callbacks work, Ctrl-C and callback exceptions cancel."""

import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import geovoronoi as gv


def big_problem(n=80):
    rng = np.random.default_rng(3)
    field = rng.uniform(1.0, 10.0, (n, n, n)).astype(np.float32)
    seeds = rng.integers(0, n, (10, 3))
    return field, np.unique(seeds, axis=0)


def long_shape_problem(n=20):
    rng = np.random.default_rng(5)
    field = rng.uniform(1.0, 10.0, (n, n + 4, n + 4)).astype(np.float32)
    seeds = np.unique(rng.integers(0, n, (8, 3)), axis=0)
    return field, seeds


def test_gil_is_released_during_a_solve():
    """While a solve runs in another thread, this thread keeps running Python code: the longest
    pause it sees is a small part of the solve (with the GIL held it would be the whole solve).
    A busy machine can deschedule this thread for a while by itself (CI runs other stages beside the
    tests), so the measurement gets three tries; with the GIL held every try fails."""
    field, seeds = big_problem()
    tries = []
    for _ in range(3):
        t0 = time.perf_counter()
        gv.voronoi(field, seeds, backend="seq")
        alone = time.perf_counter() - t0
        worker = threading.Thread(target=gv.voronoi, args=(field, seeds), kwargs=dict(backend="seq"))
        ticks = []
        worker.start()
        while worker.is_alive():
            ticks.append(time.perf_counter())
            time.sleep(0.001)
        worker.join()
        longest = float(np.diff(ticks).max()) if len(ticks) > 1 else alone
        tries.append(f"{len(ticks)} ticks, longest pause {longest:.3f} s during a {alone:.3f} s solve")
        if len(ticks) > 10 and longest < 0.5 * alone:
            return
    pytest.fail("this thread was held up during the solve in every try: " + "; ".join(tries))


def test_two_threads_solve_side_by_side():
    """Solves in two threads at once (the GIL is released, so they run in C++ together) give the bytes
    of the same solves run one after the other. Not a timing test: how much faster two threads are is
    a benchmark figure, not something a unit test on a shared machine can assert."""
    problems = [big_problem(48), big_problem(56)]
    serial = [gv.voronoi(f, s, backend="seq") for f, s in problems]
    out = [None, None]
    start = threading.Barrier(2)

    def one(i):
        start.wait()
        out[i] = gv.voronoi(*problems[i], backend="seq")

    threads = [threading.Thread(target=one, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(out, serial):
        assert a.distance.tobytes() == b.distance.tobytes()
        assert a.label.tobytes() == b.label.tobytes()


def test_progress_with_a_tqdm_like_update():
    field, seeds = long_shape_problem()
    total = []
    gv.shape_functions(field, seeds, method="distance_ratio", backend="seq", progress=total.append)
    assert len(total) >= 2 and all(x > 0 for x in total)
    assert sum(total) == pytest.approx(100.0)


def test_exception_in_progress_cancels_and_propagates():
    field, seeds = long_shape_problem()
    calls = []

    def progress(x):
        calls.append(x)
        if len(calls) == 2:
            raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        gv.shape_functions(field, seeds, method="sibson", backend="seq", batch_size=64, progress=progress)
    assert len(calls) == 2
    assert sum(calls) < 100.0
    # the package still works afterwards
    assert gv.voronoi(field, seeds, backend="seq").label.max() == len(seeds) - 1


@pytest.fixture
def sigint_raises():
    """Python's own Ctrl-C handler: a process started in the background (`cmd &` in a script, as CI
    may do) inherits SIGINT as ignored, and then Python installs no handler."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals need the main thread")
def test_ctrl_c_cancels_a_long_computation(sigint_raises):
    """SIGINT (what Ctrl-C sends), from another process, while the library computes: the next progress
    report runs Python's signal handler and cancels. The signal is sent once the computation has
    reported progress (it has started), whatever the machine's speed; run to its end the problem takes
    seconds (Sibson, 40x44x44), far longer than starting `kill`."""
    field, seeds = long_shape_problem(40)
    seen, killers = [], []

    def progress(x):
        seen.append(x)
        if len(seen) == 1:  # from another process, not raised here: the library is computing when it lands
            # The signal may land while Popen is still returning (`kill` is quick), and then
            # KeyboardInterrupt is raised here before the append: the first report is what says the
            # computation started, not the list of killers.
            killers.append(subprocess.Popen(["kill", "-INT", str(os.getpid())]))

    interrupted = False
    try:
        gv.shape_functions(field, seeds, method="sibson", backend="seq", batch_size=32, progress=progress)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        for k in killers:
            try:
                k.wait()
            except KeyboardInterrupt:  # it landed after the computation: the assertions below say so
                pass
    assert seen, "no progress was reported"
    assert interrupted and sum(seen) < 100.0, f"the computation ran to the end ({sum(seen):.0f} % reported)"
    assert gv.voronoi(field, seeds, backend="seq").distance.dtype == np.float32


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals need the main thread")
def test_sigint_raised_in_the_progress_callable_cancels(sigint_raises):
    field, seeds = long_shape_problem()
    seen = []

    def progress(x):
        seen.append(x)
        if len(seen) == 2:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        gv.shape_functions(field, seeds, method="sibson", backend="seq", batch_size=32, progress=progress)
    assert len(seen) == 2


@pytest.mark.parametrize("backend", ["seq", "thrust"])
def test_voronoi_progress_is_incremental_and_cancels(backend, sigint_raises):
    """voronoi() reports progress from inside the solve (solve_options::progress), and Ctrl-C (SIGINT
    raised in the callable) cancels the solve with KeyboardInterrupt; a later solve is unaffected."""
    if backend not in gv.backends():
        pytest.skip(f"the {backend} backend is not built into this package")
    rng = np.random.default_rng(7)
    field = rng.uniform(1.0, 5.0, size=(48, 64, 64)).astype(np.float32)
    seeds = np.array([[0, 0, 0], [47, 63, 63]])
    seen = []
    gv.voronoi(field, seeds, backend=backend, progress=seen.append)
    assert len(seen) > 2, "the solve reported only its completion"
    assert sum(seen) == pytest.approx(100.0)
    calls = []

    def progress(x):
        calls.append(x)
        if len(calls) == 2:
            signal.raise_signal(signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        gv.voronoi(field, seeds, backend=backend, progress=progress)
    assert sum(calls) < 100.0
    assert gv.voronoi(field, seeds, backend=backend).label.max() == 1

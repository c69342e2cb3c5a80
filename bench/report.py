#!/usr/bin/env python3
"""The markdown tables of docs/benchmarks.md, and before/after comparisons, from Google Benchmark JSON.

    bench/report.py tables DIR [--section NAME ...]    the tables of docs/benchmarks.md
    bench/report.py compare BEFORE AFTER [--threshold 3] [--strict]
    bench/report.py compare DIR                        DIR/before against DIR/current

DIR is what bench/run_all.sh writes (or any folder, or list, of JSON files written with
`--benchmark_out=F --benchmark_out_format=json`). bench/run_all.sh names its files
`<executable>[.t<OMP threads>].r<round>[.c<case>].json` and writes DIR/meta.txt (commit, compiler, CPU model);
where a file name says nothing, the executable comes from the JSON context and the thread count is
unknown. A folder that holds `current/` is read from there.

Every figure is the median over the repetitions and rounds of a case (`--benchmark_repetitions`,
several rounds of bench/run_all.sh); aggregate rows (mean, median, ...) are used only when a file
holds no single repetitions. Ratios compare medians from the same process where the tables say so
(the `seq` cases linked into bench_voronoi_thrust, the update cases beside their full solve).

compare prints, per case present on both sides (same executable, same thread count), the median
before and after, after / before, the range of each side, and flags a case whose median is more
than --threshold percent slower (3 by default); `--strict` makes the exit status 1 when any case is
flagged. Work counters (expansions, settled voxels, rows recomputed, ...) that differ are listed.

Python 3 standard library only; runs with /usr/bin/python3.
"""

import argparse
import glob
import json
import math
import os
import re
import signal
import statistics
import sys

# ---- reading ----------------------------------------------------------------------------------------

# Google Benchmark appends the run's settings to the name: .../iterations:5/real_time, /min_time:1.000, ...
_SETTING = re.compile(r"/(iterations|min_time|min_warmup_time|repeats|threads|real_time|manual_time|process_time)"
                      r"(:[^/]*)?$")
_STANDARD = {"name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
             "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name",
             "aggregate_unit", "error_occurred", "error_message", "label", "big_o", "rms", "skipped", "skip_message"}
# counters that are rates or times, not work: left out of compare's "work counters changed"
_TIMING_COUNTERS = {"iterations", "voxels_per_second", "ns_per_voxel", "updates_per_s", "full_cpu_s", "full_kept_cpu_s",
                    "full_after_cpu_s", "speedup_cpu", "peak_rss_MB", "achieved_bytes_per_second",
                    "resident_bytes_per_voxel"}
_UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def case_name(run_name):
    """`voronoi/seq/gradient/64/10/26/iterations:5/real_time` -> `voronoi/seq/gradient/64/10/26`."""
    name = run_name
    while True:
        stripped = _SETTING.sub("", name)
        if stripped == name:
            return name
        name = stripped


def parse_file_name(base):
    """bench/run_all.sh's `<executable>[.t<threads>][.update].r<round>[.c<case>].json` -> (exe, threads, round);
    (None, None, None) for other names."""
    parts = base[:-5].split(".") if base.endswith(".json") else []
    if len(parts) < 2 or not any(re.fullmatch(r"r\d+", p) for p in parts[1:]):
        return None, None, None
    threads = rnd = None
    for p in parts[1:]:
        if re.fullmatch(r"t\d+", p):
            threads = int(p[1:])
        elif re.fullmatch(r"r\d+", p):
            rnd = int(p[1:])
    return parts[0], threads, rnd


class Stat:
    """The repetitions of one case in one executable at one thread count."""

    def __init__(self):
        self.real = []  # seconds per iteration, one value per repetition
        self.cpu = []
        self.counters = {}  # name -> list of values
        self.errors = []
        self.from_aggregate = False

    def add(self, b, aggregate=False):
        if b.get("error_occurred"):
            self.errors.append(b.get("error_message", "error"))
            return
        scale = _UNIT.get(b.get("time_unit", "ns"), 1e-9)
        self.real.append(b["real_time"] * scale)
        self.cpu.append(b["cpu_time"] * scale)
        self.from_aggregate = self.from_aggregate or aggregate
        for k, v in b.items():
            # a user counter named `iterations` (bench_voronoi_cuda's engine iterations) replaces
            # Google Benchmark's own key of that name in the JSON; keep it as a counter too
            if (k not in _STANDARD or k == "iterations") and isinstance(v, (int, float)):
                self.counters.setdefault(k, []).append(float(v))

    @property
    def ok(self):
        return bool(self.real)

    @property
    def time(self):
        return statistics.median(self.real)

    @property
    def cpu_time(self):
        return statistics.median(self.cpu)

    def counter(self, name, default=None):
        v = self.counters.get(name)
        return statistics.median(v) if v else default


class Runs:
    """Every case of a set of JSON files, keyed by (executable, OMP threads or None, case)."""

    def __init__(self, paths):
        self.stats = {}
        self.contexts = []  # (executable, threads, round, context)
        self.meta = {}
        self.extra = {}  # name -> text (python.txt)
        files = []
        for p in paths:
            if os.path.isdir(p):
                sub = os.path.join(p, "current")
                d = sub if os.path.isdir(sub) and not glob.glob(os.path.join(p, "*.json")) else p
                files += sorted(glob.glob(os.path.join(d, "*.json")))
                for m in (os.path.join(p, "meta.txt"), os.path.join(d, "meta.txt")):
                    self._read_meta(m)
                for t in sorted(glob.glob(os.path.join(d, "*.txt"))):
                    if os.path.basename(t) != "meta.txt":
                        with open(t, encoding="utf-8", errors="replace") as f:
                            self.extra[os.path.basename(t)] = f.read()
            else:
                files.append(p)
        for f in files:
            self._read(f)

    def _read_meta(self, path):
        if os.path.isfile(path):
            with open(path, encoding="utf-8", errors="replace") as f:
                for line in f:
                    if "=" in line:
                        k, v = line.rstrip("\n").split("=", 1)
                        self.meta[k.strip()] = v.strip()

    def _read(self, path):
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
        except (OSError, ValueError) as e:
            print(f"warning: {path}: {e}", file=sys.stderr)
            return
        ctx = data.get("context", {})
        exe, threads, rnd = parse_file_name(os.path.basename(path))
        if exe is None:
            exe = os.path.basename(ctx.get("executable", path))
        self.contexts.append((exe, threads, rnd, ctx))
        benches = data.get("benchmarks", [])
        has_single = {b.get("run_name", b["name"]) for b in benches if b.get("run_type", "iteration") == "iteration"}
        for b in benches:
            run_name = b.get("run_name", b["name"])
            if b.get("run_type", "iteration") == "aggregate":
                # only when the file kept aggregates alone (--benchmark_report_aggregates_only)
                if run_name in has_single or b.get("aggregate_name") != "median":
                    continue
                agg = True
            else:
                agg = False
            key = (exe, threads, case_name(run_name))
            self.stats.setdefault(key, Stat()).add(b, agg)

    # -- look-ups --
    def get(self, case, exe=None, threads=None, any_threads=True):
        """The Stat of @p case; @p exe a name or a list of names in order of preference."""
        exes = [exe] if isinstance(exe, str) else (exe or [None])
        for e in exes:
            best = None
            for (ke, kt, kc), s in self.stats.items():
                if kc != case or not s.ok or (e is not None and ke != e):
                    continue
                if threads is not None and kt != threads and not (any_threads and kt is None):
                    continue
                if best is None or (kt == threads and best[0] != threads):
                    best = (kt, s)
            if best:
                return best[1]
        return None

    def cases(self, pattern, exe=None):
        rx = re.compile(pattern)
        return sorted({c for (e, _, c) in self.stats if rx.search(c) and (exe is None or e == exe)})

    def threads_of(self, exe):
        return sorted({t for (e, t, _) in self.stats if e == exe and t is not None})


# ---- formatting -------------------------------------------------------------------------------------

def fmt_time(s):
    if s is None:
        return ""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("us", 1e-6)):
        if s >= scale:
            v = s / scale
            return f"{v:.3g} {unit}" if v < 1000 else f"{v:.0f} {unit}"
    return f"{s * 1e9:.3g} ns"


def fmt_ratio(a, b):
    """a / b as '4.11x'."""
    if a is None or b is None or b == 0:
        return ""
    return f"{a / b:.3g}x" if a / b < 100 else f"{a / b:.0f}x"


def fmt_num(v, digits=3):
    """Counts with thousands separators, other values to about @p digits significant digits."""
    if v is None:
        return ""
    if not math.isfinite(v):
        return str(v)
    if v == int(v) and abs(v) < 1e15:
        return f"{int(v):,}"
    if abs(v) >= 10 ** digits:
        return f"{v:,.0f}"
    return f"{v:.{digits}g}"


def table(header, rows, align=None):
    if not rows:
        return ""
    align = align or ["---"] + ["---:"] * (len(header) - 1)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join("" if c is None else str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def t(stat):
    return stat.time if stat else None


# ---- the sections of docs/benchmarks.md ---------------------------------------------------------------

FIELDS = ["constant", "gradient", "steak"]
HEADLINE = ["gradient/128/10/26", "gradient/256/10/26", "steak/128/10/26", "constant/128/10/26", "mri/221/20/26"]


def section_machine(r):
    out = ["### Machine and runs\n"]
    m = r.meta
    if m:
        keys = [("cpu_model", "CPU"), ("cpus", "CPUs"), ("compiler", "compiler"), ("flags", "flags"),
                ("commit", "commit"), ("commit_before", "before (commit)"), ("started", "started"),
                ("finished", "finished"), ("load_start", "load average at the start"),
                ("repetitions", "repetitions"), ("rounds", "rounds"), ("omp_threads", "OpenMP threads")]
        for k, label in keys:
            if m.get(k):
                out.append(f"* {label}: {m[k]}")
        out.append("")
    # one line for every process of the run: the clock and cache Google Benchmark saw, the range of the
    # 1-minute load average at each start (each JSON file holds its own)
    clocks, l3s, loads = set(), set(), []
    for _exe, _threads, _rnd, ctx in r.contexts:
        clocks.add(f"{ctx.get('num_cpus', '')} x {ctx.get('mhz_per_cpu', '')} MHz")
        l3s.update(f"{c['size'] / 2**20:.0f} MiB" for c in ctx.get("caches", []) if c.get("level") == 3)
        if ctx.get("load_avg"):
            loads.append(ctx["load_avg"][0])
    if r.contexts:
        line = f"* processes: {len(r.contexts)}; CPUs {', '.join(sorted(clocks))}"
        if l3s:
            line += f"; L3 {', '.join(sorted(l3s))}"
        if loads:
            line += f"; 1-minute load average at their starts {min(loads):.2f} to {max(loads):.2f}"
        out.append(line + "\n")
    return "\n".join(out)


def section_sofa(r):
    exe = ["bench_voronoi_cpu", "bench_voronoi_sofa_set", None]
    rows = []
    for f in FIELDS:
        for n in (64, 128, 256):
            for s in (10, 100, 1000):
                c = f"{f}/{n}/{s}/26"
                a = r.get("voronoi/seq/" + c, ["bench_voronoi_cpu", "bench_voronoi_seq", None])
                b = r.get("voronoi/sofa_set/" + c, exe)
                if not a or not b:
                    continue
                rows.append([c, fmt_time(a.time), fmt_num(a.counter("ns_per_voxel")), fmt_time(b.time),
                             fmt_num(b.counter("ns_per_voxel")), fmt_ratio(b.time, a.time),
                             fmt_num(b.counter("relax_per_voxel"))])
    if not rows:
        return ""
    return ("### seq against sofa_set (26-connected, min_stiffness)\n\n" +
            table(["case", "seq", "seq ns/voxel", "sofa_set", "sofa_set ns/voxel", "sofa_set / seq",
                   "sofa_set relax/voxel"], rows))


def section_seq_matrix(r):
    exe = ["bench_voronoi_cpu", "bench_voronoi_seq", None]
    sizes = [n for n in (64, 128, 256) if r.cases(f"^voronoi/seq/[a-z]+/{n}/")]
    if not sizes:
        return ""
    rows = []
    for f in FIELDS:
        for s in (10, 100, 1000):
            for k in (6, 26):
                row, per = [f, s, k], []
                for n in sizes:
                    st = r.get(f"voronoi/seq/{f}/{n}/{s}/{k}", exe)
                    row += [fmt_time(t(st)), fmt_num(st.counter("ns_per_voxel")) if st else ""]
                    per.append(st.counter("ns_per_voxel") if st else None)
                if all(p is None for p in per):
                    continue
                if len(sizes) > 1:
                    row.append(fmt_ratio(per[-1], per[0]) if per[0] and per[-1] else "")
                rows.append(row)
    head = ["field", "seeds", "conn"]
    for n in sizes:
        head += [f"{n}^3", "ns/voxel"]
    if len(sizes) > 1:
        head.append(f"ns/voxel {sizes[-1]}^3 / {sizes[0]}^3")
    out = "### seq, the whole matrix\n\n" + table(head, rows, ["---"] + ["---:"] * (len(head) - 1))
    mri = r.get("voronoi/seq/mri/221/20/26", exe)
    if mri:
        out += (f"\n`voronoi/seq/mri/221/20/26` (221 x 271 x 69, 20 seeds): {fmt_time(mri.time)}, "
                f"{fmt_num(mri.counter('ns_per_voxel'))} ns per grid voxel.\n")
    return out


def section_thrust(r):
    exe = "bench_voronoi_thrust"
    threads = r.threads_of(exe) or [None]
    backends = sorted({c.split("/")[1] for c in r.cases(r"^voronoi/thrust_[a-z]+/[a-z]+/\d+/", exe)})
    if not backends:
        return ""
    out = []
    all_threads = threads
    for be in backends:
        # OMP_NUM_THREADS sets the OpenMP system's threads only (TBB takes every core): one column there
        threads = all_threads if be == "thrust_omp" else all_threads[-1:]
        cases = ["/".join(c.split("/")[2:]) for c in r.cases(rf"^voronoi/{be}/[a-z]+/\d+/\d+/\d+$", exe)]
        cases.sort(key=lambda c: (HEADLINE.index(c) if c in HEADLINE else len(HEADLINE), c))
        head = ["case", "seq"]
        for th in threads:
            lab = "" if th is None else f", {th} thr."
            head += [f"{be}{lab}", f"seq / {be}{lab}"]
        if len(threads) > 1:
            head.append(f"{threads[0]} -> {threads[-1]} threads")
        head.append("expansions/voxel")
        rows = []
        for c in cases:
            seq_all = r.get("voronoi/seq/" + c, exe)
            row = [c, fmt_time(t(seq_all))]
            times = []
            last = None
            for th in threads:
                st = r.get(f"voronoi/{be}/{c}", exe, th, any_threads=False) if th is not None else r.get(
                    f"voronoi/{be}/{c}", exe)
                sq = r.get("voronoi/seq/" + c, exe, th, any_threads=False) if th is not None else seq_all
                row += [fmt_time(t(st)), fmt_ratio(t(sq), t(st))]
                times.append(t(st))
                last = st or last
            if len(threads) > 1:
                row.append(fmt_ratio(times[0], times[-1]))
            row.append(fmt_num(last.counter("relaxations_per_voxel"), 5) if last else "")
            rows.append(row)
        out.append(f"### {be} against seq (the same process)\n\n" + table(head, rows))
    return "\n".join(out)


def section_backends(r):
    """Every backend on the headline cases, side by side (CPU and, where they ran, GPU backends)."""
    found = {}
    for (e, th, c), s in r.stats.items():
        m = re.match(r"^voronoi/([a-z_]+)/([a-z]+/\d+/\d+/\d+)$", c)
        if m and m.group(2) in HEADLINE and s.ok and m.group(1) != "seq":
            found.setdefault((m.group(1), th), {})[m.group(2)] = s
    order = ["sofa_set", "thrust_omp", "thrust_tbb", "thrust_cuda", "cuda", "cuda_end_to_end"]
    picked = sorted(found, key=lambda k: (order.index(k[0]) if k[0] in order else 99, k[0], k[1] or 0))
    if not picked:
        return ""
    seq_exe = ["bench_voronoi_cpu", "bench_voronoi_seq", None]
    head = ["case", "seq"] + [be if th is None else f"{be} ({th} thr.)" for be, th in picked]
    rows = []
    for c in HEADLINE:
        if not any(c in found[k] for k in picked):
            continue
        base = r.get("voronoi/seq/" + c, seq_exe)
        row = [c, fmt_time(t(base))]
        for k in picked:
            st = found[k].get(c)
            cell = fmt_time(t(st))
            if st and base:
                cell += f" ({fmt_ratio(base.time, st.time)})"
            row.append(cell)
        rows.append(row)
    return "### Every backend on the headline cases (in brackets: seq / backend)\n\n" + table(head, rows)


def section_queue(r):
    kinds = ["radix_heap", "binary_heap", "std_set"]
    rows = []
    for n in (64, 128, 256):
        sts = [r.get(f"queue/{k}/gradient/{n}") for k in kinds]
        if not any(sts):
            continue
        row = [f"gradient {n}^3"]
        for s in sts:
            row += [fmt_time(t(s)), fmt_ratio(t(s), t(sts[0]))]
        rows.append(row)
    if not rows:
        return ""
    head = ["case"]
    for k in kinds:
        head += [k, "/ radix_heap"]
    return "### Priority queue (bench_queue_ablation: the same engine, only the queue differs)\n\n" + table(head, rows)


def section_sparse(r):
    scratch = ["paged16", "paged32", "paged64", "paged128"]
    ops = [("insert", "table1"), ("insert", "steak"), ("bounded", "128cube_100")]
    rows = []
    for op, c in ops:
        sts = [r.get(f"sparse/{op}/{s}/{c}") for s in scratch]
        dense = r.get(f"sparse/dense/seq/{c}")
        if not any(sts):
            continue
        # the counter is an inverted rate (kIsRate | kInvert): seconds per voxel, printed here in ns
        def ns(st):
            v = st.counter("ns_per_voxel") if st else None
            return None if v is None else v * 1e9
        p64 = ns(sts[2])
        dn = ns(dense)
        rows.append([f"{op} {c}"] + [fmt_num(ns(s)) if s else "" for s in sts] +
                    [fmt_num(dn), fmt_ratio(p64, dn)])
    out = ""
    if rows:
        out += ("### Sparse searches (bench_seq_sparse): ns per voxel by page size\n\n" +
                table(["search", "pages of 16", "32", "64 (shipped)", "128", "dense solve", "64 / dense"], rows))
    api = []
    for op, c in (("bounded_api", "128cube_100"), ("insert_api", "steak")):
        a, b = r.get(f"sparse/{op}/seq/{c}"), r.get(f"sparse/{op}/seq_ws/{c}")
        if a or b:
            api.append([f"{op} {c}", fmt_time(t(a)), fmt_time(t(b)), fmt_ratio(t(a), t(b))])
    if api:
        out += "\n" + table(["front-end call", "seq (fresh scratch)", "seq(ws) (workspace)", "fresh / ws"], api)
    return out


EDITS = ["cut20", "carve8", "stiffen8", "soften8", "add_node", "move_node", "move_node_largest", "sweep",
         "sweep_with_cut", "cut20_cold", "add_node_cold"]


def section_update(r):
    out = []
    for be in ("seq", "thrust_omp"):
        exe = ["bench_voronoi_cpu", "bench_voronoi_seq", None] if be == "seq" else ["bench_voronoi_thrust"]
        threads = r.threads_of("bench_voronoi_thrust") if be == "thrust_omp" else []
        th = threads[-1] if threads else None
        full = r.get(f"voronoi/{be}/steak128", exe, th)
        cold = r.get(f"voronoi/{be}/steak128_cold", exe, th)
        if not full:
            continue
        rows = [[f"`voronoi/{be}/steak128` (full solve with parents)", fmt_time(full.time), "", "1", ""]]
        if cold:
            rows.append([f"`voronoi/{be}/steak128_cold`", fmt_time(cold.time), "", "1 (cold)", ""])
        for e in EDITS:
            st = r.get(f"update/{be}/steak128/{e}", exe, th)
            if not st:
                continue
            work = []
            for k, lab in (("invalidated", "invalidated"), ("lowered", "lowered"),
                           ("invalidated_per_step", "invalidated per step")):
                v = st.counter(k)
                if v:
                    work.append(f"{fmt_num(v)} {lab}")
            ref = cold if e.endswith("_cold") and cold else full
            rate = st.counter("updates_per_s")
            rows.append([f"`{e}`", fmt_time(st.time) + (" per step" if e.startswith("sweep") else ""),
                         ", ".join(work), fmt_ratio(ref.time, st.time), f"{rate:.0f} updates/s" if rate else ""])
        lab = f" ({th} OpenMP threads)" if th else ""
        out.append(f"### Updates after an edit, {be}{lab}: steak 128 x 96 x 32, 12 nodes\n\n" +
                   table(["case", "time", "voxels", "full solve / update", "rate"], rows))
        if be == "thrust_omp":
            sq = r.get("voronoi/seq/steak128", exe, th)
            if sq:
                out.append(f"seq's full solve in the same process: {fmt_time(sq.time)} "
                           f"(seq / thrust_omp {fmt_ratio(sq.time, full.time)}).\n")
    return "\n".join(out)


SHAPE_CASES = ["table1", "128cube_100", "beam", "steak64", "at1000", "steak128"]
METHODS = ["distance_ratio", "sibson", "laplace"]
# the paper's figures (Toss, Comba, Raffin 2016, Table 1: 100x40x20, 20 nodes)
PAPER = {("table1", "sibson"): "81 s seq, 18.6 s Tesla K40"}


def section_shape(r):
    th_omp = r.threads_of("bench_shape_thrust_omp")
    th = th_omp[-1] if th_omp else None
    rows = []
    for c in SHAPE_CASES:
        for m in METHODS:
            a = r.get(f"shape/{m}/seq/{c}", "bench_shape_seq")
            b = r.get(f"shape/{m}/thrust_omp/{c}", "bench_shape_thrust_omp", th)
            if not a and not b:
                continue
            ref = a or b
            rows.append([c, m, fmt_time(t(a)), fmt_time(t(b)), fmt_ratio(t(a), t(b)),
                         fmt_num(ref.counter("visits_per_query")), fmt_num(ref.counter("single_owner_rows")),
                         " / ".join(fmt_num(x.counter("peak_rss_MB")) if x else "-" for x in (a, b)),
                         PAPER.get((c, m), "")])
    if not rows:
        return ""
    lab = f"thrust_omp ({th} thr.)" if th else "thrust_omp"
    out = ("### Shape functions: every voxel's weights (`shape/<method>/<backend>/<case>`)\n\n" +
           table(["case", "method", "seq", lab, f"seq / {lab}", "settled voxels per query",
                  "rows without search", "peak RSS MB (seq / thrust_omp)", "paper"], rows,
                 ["---", "---"] + ["---:"] * 6 + ["---"]))
    var = []
    for c in SHAPE_CASES:
        for m in METHODS:
            for v, base, exe in (("seq_materialise", "seq", "bench_shape_seq"), ("seq_noreuse", "seq", "bench_shape_seq"),
                                 ("seq_nofilter", "seq", "bench_shape_seq"),
                                 ("thrust_omp_nofilter", "thrust_omp", "bench_shape_thrust_omp")):
                s = r.get(f"shape/{m}/{v}/{c}", exe, th if "thrust" in v else None)
                d = r.get(f"shape/{m}/{base}/{c}", exe, th if "thrust" in v else None)
                if s and d:
                    var.append([c, m, v, fmt_time(s.time), fmt_time(d.time), fmt_ratio(s.time, d.time),
                                fmt_num(s.counter("peak_rss_MB")), fmt_num(d.counter("peak_rss_MB"))])
    if var:
        out += ("\nThe same cases with one part of the search switched off:\n\n" +
                table(["case", "method", "variant", "variant", "default", "variant / default", "peak RSS MB variant",
                       "default"], var, ["---", "---", "---"] + ["---:"] * 5))
    return out


def section_shape_update(r):
    rows = []
    for exe, be in (("bench_shape_seq", "seq"), ("bench_shape_thrust_omp", "thrust_omp")):
        th = (r.threads_of(exe) or [None])[-1]
        for m in ("distance_ratio", "distance_ratio_kept", "sibson", "laplace"):
            for e in ("cut20", "carve8", "add_node"):
                st = r.get(f"shape_update/{m}/{be}/steak128/{e}", exe, th)
                if not st:
                    continue
                rec, rows_n = st.counter("recomputed"), st.counter("rows")
                verified = st.counter("verified")
                rows.append([f"{m}/{be}/{e}", fmt_time(st.time), fmt_time(st.cpu_time),
                             fmt_num(st.counter("full_cpu_s")) + " s",
                             f"{st.counter('speedup_cpu', 0):.3g}x",
                             f"{fmt_num(rec)} ({100 * rec / rows_n:.1f} %)" if rec is not None and rows_n else "",
                             fmt_num(st.counter("changed")), fmt_num(st.counter("changed_voxels")),
                             "" if verified is None else ("yes" if verified == 1 else "**no**")])
    if not rows:
        return ""
    return ("### Shape functions after an edit (`shape_update/<method>/<backend>/steak128/<edit>`)\n\n" +
            table(["case", "update (wall)", "update (CPU)", "full computation (CPU)", "full / update (CPU)",
                   "rows recomputed", "rows changed", "X", "verified"], rows))


def section_cuda(r):
    out = []
    rows = []
    for c in r.cases(r"^voronoi/cuda/"):
        st = r.get(c)
        rest = "/".join(c.split("/")[2:])
        sq, so = r.get("voronoi/seq/" + rest), r.get("voronoi/sofa_set/" + rest)
        n = int(rest.split("/")[1])
        cp = r.get(f"copy/cuda/{n}")
        bw = cp.counter("achieved_bytes_per_second") if cp else None
        solve_bw = 12.0 * n ** 3 / st.time if st else None
        rows.append([rest, fmt_time(t(st)), fmt_num(st.counter("iterations")), fmt_ratio(t(sq), t(st)),
                     fmt_ratio(t(so), t(st)), f"{solve_bw / bw:.2f}" if bw else "",
                     fmt_num(st.counter("model_bytes_per_voxel")), fmt_num(st.counter("resident_bytes_per_voxel"))])
    if rows:
        out.append("### CUDA kernel backend (device time, CUDA events)\n\n" +
                   table(["case", "cuda", "iterations", "seq / cuda", "sofa_set / cuda",
                          "12 B/voxel over the time / copy bandwidth", "model B/voxel", "resident B/voxel"], rows))
    e2e = [[c.split("/", 2)[2], fmt_time(t(r.get(c))), fmt_time(t(r.get("voronoi/cuda/" + c.split("/", 2)[2])))]
           for c in r.cases(r"^voronoi/cuda_end_to_end/")]
    if e2e:
        out.append(table(["case", "whole call (uploads, downloads)", "device solve alone"], e2e))
    cp = [[c, fmt_time(t(r.get(c))), f"{r.get(c).counter('achieved_bytes_per_second', 0) / 1e9:.0f} GB/s"]
          for c in r.cases(r"^copy/cuda/")]
    if cp:
        out.append(table(["copy case", "time", "achieved"], cp))
    return "\n".join(out)


def section_python(r):
    text = r.extra.get("python.txt")
    return ("### Python package (bench/python/bench_python.py, output as printed)\n\n```text\n" + text.strip() +
            "\n```\n") if text else ""


SECTIONS = {"machine": section_machine, "backends": section_backends, "sofa": section_sofa,
            "seq": section_seq_matrix, "thrust": section_thrust, "queue": section_queue, "sparse": section_sparse,
            "update": section_update, "shape": section_shape, "shape_update": section_shape_update,
            "cuda": section_cuda, "python": section_python}


def cmd_tables(a):
    r = Runs(a.paths)
    if not r.stats:
        sys.exit("no benchmark results in " + " ".join(a.paths))
    for name in a.section or list(SECTIONS):
        text = SECTIONS[name](r)
        if text:
            print(text)
    errors = [(k, s.errors) for k, s in r.stats.items() if s.errors]
    for (e, th, c), msgs in sorted(errors):
        print(f"**error** in {e} {c}: {msgs[0]}")


# ---- before / after ---------------------------------------------------------------------------------

def cmd_compare(a):
    if len(a.paths) == 1:
        before_p, after_p = os.path.join(a.paths[0], "before"), os.path.join(a.paths[0], "current")
    elif len(a.paths) == 2:
        before_p, after_p = a.paths
    else:
        sys.exit("compare takes DIR (with before/ and current/) or BEFORE AFTER")
    before, after = Runs([before_p]), Runs([after_p])
    limit = 1.0 + a.threshold / 100.0
    keys = sorted(set(before.stats) & set(after.stats), key=lambda k: (k[0], k[1] or 0, k[2]))
    rows, flagged = [], []
    for k in keys:
        b, n = before.stats[k], after.stats[k]
        if not b.ok or not n.ok:
            continue
        ratio = n.time / b.time
        flag = ""
        if ratio > limit:
            flag = "**slower**" + (" (ranges overlap)" if min(n.real) <= max(b.real) else "")
            flagged.append(k)
        elif ratio < 1.0 / limit:
            flag = "faster" + (" (ranges overlap)" if max(n.real) >= min(b.real) else "")
        work = []
        for c in sorted(set(b.counters) & set(n.counters) - _TIMING_COUNTERS):
            x, y = b.counter(c), n.counter(c)
            if x != y and abs(x - y) > 1e-9 * max(abs(x), abs(y)):
                work.append(f"{c} {fmt_num(x, 5)} -> {fmt_num(y, 5)}")
        exe, th, case = k
        rows.append([case, exe + ("" if th is None else f" ({th} thr.)"), fmt_time(b.time), fmt_time(n.time),
                     f"{ratio:.3f}", f"{fmt_time(min(b.real))} - {fmt_time(max(b.real))}",
                     f"{fmt_time(min(n.real))} - {fmt_time(max(n.real))}", len(b.real), len(n.real), flag,
                     "; ".join(work)])
    print(f"### Before / after (medians; flagged: more than {a.threshold:g} % slower)\n")
    print(table(["case", "executable", "before", "after", "after / before", "before: range", "after: range",
                 "runs before", "runs after", "", "work counters changed"], rows,
                ["---", "---"] + ["---:"] * 7 + ["---", "---"]))
    only_b = sorted({k[2] for k in set(before.stats) - set(after.stats)})
    only_a = sorted({k[2] for k in set(after.stats) - set(before.stats)})
    if only_b:
        print("Only before: " + ", ".join(only_b) + "\n")
    if only_a:
        print("Only after: " + ", ".join(only_a) + "\n")
    ratios = [after.stats[k].time / before.stats[k].time for k in keys if before.stats[k].ok and after.stats[k].ok]
    if ratios:
        print(f"{len(ratios)} cases; after / before: median {statistics.median(ratios):.3f}, "
              f"from {min(ratios):.3f} to {max(ratios):.3f}; {len(flagged)} flagged slower than {a.threshold:g} %.")
    for k in flagged:
        b, n = before.stats[k], after.stats[k]
        print(f"* slower: {k[2]} ({k[0]}{'' if k[1] is None else f', {k[1]} threads'}): "
              f"{fmt_time(b.time)} -> {fmt_time(n.time)} (+{100 * (n.time / b.time - 1):.1f} %)")
    if flagged and a.strict:
        sys.exit(1)


def main(argv=None):
    if hasattr(signal, "SIGPIPE"):  # `report.py ... | head` ends quietly
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    sub = ap.add_subparsers(dest="cmd")
    p = sub.add_parser("tables", help="the markdown tables of docs/benchmarks.md")
    p.add_argument("paths", nargs="+", help="folders (bench/run_all.sh output) or JSON files")
    p.add_argument("--section", action="append", choices=list(SECTIONS), help="only these sections")
    p.set_defaults(func=cmd_tables)
    p = sub.add_parser("compare", help="before/after per case")
    p.add_argument("paths", nargs="+", help="DIR (with before/ and current/) or BEFORE AFTER")
    p.add_argument("--threshold", type=float, default=3.0, help="percent slower that is flagged (3)")
    p.add_argument("--strict", action="store_true", help="exit status 1 when a case is flagged")
    p.set_defaults(func=cmd_compare)
    args = ap.parse_args(argv)
    if not args.cmd:
        ap.print_help()
        return 2
    args.func(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())

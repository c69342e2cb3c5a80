#!/usr/bin/env python3
"""Turn bench_voronoi_cpu's JSON output into the markdown tables of docs/benchmarks.md.

    build/bench/bench_voronoi_cpu --benchmark_out=bench.json --benchmark_out_format=json
    python3 bench/voronoi/cpu.py bench.json

Standard library only. Rows whose CPU time is below 85 % of their wall-clock time (the process was
waiting for the CPU, i.e. the machine was busy) are marked with '*'. With --benchmark_repetitions,
the fastest repetition of each case is used.
"""
import json
import sys


def load(path):
    runs = json.load(open(path))
    res = {}
    for b in runs["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        name = b["name"].split("/iterations")[0]
        parts = name.split("/")
        if len(parts) != 6 or parts[0] != "voronoi":
            continue
        _, be, field, n, s, c = parts
        key = (be, field, int(n), int(s), int(c))
        if key not in res or b["real_time"] < res[key]["real_time"]:
            res[key] = b
    return runs["context"], res


def ms(b):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
    return b["real_time"] * scale, b["cpu_time"] * scale


def flag(b):
    real, cpu = ms(b)
    return "*" if cpu < 0.85 * real else ""


def main(path):
    ctx, res = load(path)
    fields = ["constant", "gradient", "steak"]
    sizes = sorted({k[2] for k in res})
    seeds = sorted({k[3] for k in res})
    print("### seq vs sofa_set (26-connected)\n")
    print("| case | seq ms (cpu) | seq us/voxel | sofa_set ms (cpu) | sofa_set us/voxel | speed-up | sofa_set relax/voxel |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for f in fields:
        for n in sizes:
            for s in seeds:
                a, b = res.get(("seq", f, n, s, 26)), res.get(("sofa_set", f, n, s, 26))
                if a is None or b is None:
                    continue
                (ar, ac), (br, bc) = ms(a), ms(b)
                print(f"| {f}/{n}/{s}/26 | {ar:.1f}{flag(a)} ({ac:.0f}) | {a['ns_per_voxel'] / 1000:.3f} "
                      f"| {br:.1f}{flag(b)} ({bc:.0f}) | {b['ns_per_voxel'] / 1000:.3f} | {br / ar:.2f}x "
                      f"| {b.get('relax_per_voxel', float('nan')):.2f} |")
    print("\n### seq, full matrix\n")
    head = " | ".join(f"{n}^3 ms | {n}^3 ns/voxel" for n in sizes)
    print(f"| field | seeds | conn | {head} | growth {sizes[0]}->{sizes[-1]} |")
    print("|---|---:|---:|" + "---:|" * (2 * len(sizes) + 1))
    for f in fields:
        for s in seeds:
            for c in (6, 26):
                row, per = [f, str(s), str(c)], []
                for n in sizes:
                    b = res.get(("seq", f, n, s, c))
                    if b is None:
                        row += ["", ""]
                        per.append(None)
                        continue
                    row += [f"{ms(b)[0]:.1f}{flag(b)}", f"{b['ns_per_voxel']:.0f}"]
                    per.append(b["ns_per_voxel"])
                if all(x is None for x in per):
                    continue
                row.append(f"{per[-1] / per[0]:.2f}x" if per[0] and per[-1] else "")
                print("| " + " | ".join(row) + " |")
    print(f"\nrun: {ctx.get('date')}, {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz, "
          f"load average at start {ctx.get('load_avg')}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: cpu.py bench.json")
    main(sys.argv[1])

#!/usr/bin/env python3
"""Is every process's resident memory flat? Reads the trace gyrocal_bench_graph --rss-out writes
(t_s,pid,process,rss_kb: one row per process per sample) and prints, per process (by pid): its
RSS at fraction --from of the run (1/6 = the first 4 h of a 24 h run), its peak, the growth after
--from (the largest RSS after it minus the RSS at it, as the benchmark prints), its RSS at the end,
the least-squares slope over the part after --from, and whether the growth stays within
--bound-mb. The run's fraction is of wall time: at the graph's own pace data time and wall time
advance together only roughly (a loaded machine slows the graph), so the point "4 h of data" is
better given in wall seconds: --from-s (and --until-s, the end of the data, to leave out the
final fits and report after it), read from the run's database (the recv_utime of the sample at
4 h of data and of the last one, from the run's start event; the benchmark's clock starts within
a second of it).

Run: tests/bench/graph/rss_flat.py /tmp/day/rss.tsv [--from 0.1667 | --from-s S] [--until-s S]
         [--bound-mb 5]
Exit 0 when every long-lived process is within the bound, 1 otherwise, 2 on bad input.
"""
import argparse
import csv
import sys


def read_traces(path):
    traces = {}  # pid -> (name, [(t_s, rss_kb)])
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = next(rows, None)
        if header != ["t_s", "pid", "process", "rss_kb"]:
            raise ValueError(f"{path}:1: header {header}, expected t_s,pid,process,rss_kb")
        for line, row in enumerate(rows, start=2):
            if len(row) != 4:
                raise ValueError(f"{path}:{line}: {len(row)} fields, expected 4")
            try:
                t, pid, kb = float(row[0]), int(row[1]), int(row[3])
            except ValueError:
                raise ValueError(f"{path}:{line}: t_s, pid or rss_kb is not a number: {row}")
            traces.setdefault(pid, (row[2], []))[1].append((t, kb))
    if not traces:
        raise ValueError(f"{path}: no samples")
    return traces


def slope_kb_per_s(points):
    n = len(points)
    if n < 2:
        return 0.0
    mt = sum(t for t, _ in points) / n
    mk = sum(k for _, k in points) / n
    var = sum((t - mt) ** 2 for t, _ in points)
    return sum((t - mt) * (k - mk) for t, k in points) / var if var > 0 else 0.0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("rss_tsv")
    p.add_argument("--from", dest="frm", type=float, default=1 / 6,
                   help="fraction of the run after which memory must be flat (default 1/6)")
    p.add_argument("--from-s", type=float, help="[s] wall time from which (instead of --from)")
    p.add_argument("--until-s", type=float, help="[s] wall time up to which (default: the end)")
    p.add_argument("--bound-mb", type=float, default=5.0,
                   help="[MB] largest growth after --from called flat (default 5)")
    p.add_argument("--data-hours", type=float,
                   help="[h] data time from --from to the end of the data, for the slope per "
                   "data hour (default: 24 x (1 - the fraction))")
    a = p.parse_args()
    if not 0 <= a.frm < 1:
        p.error(f"--from {a.frm}: valid is 0 <= F < 1")
    try:
        traces = read_traces(a.rss_tsv)
    except (OSError, ValueError) as e:
        print(f"rss_flat: {e}", file=sys.stderr)
        return 2
    t_begin = min(pts[0][0] for _, pts in traces.values())
    t_end = max(pts[-1][0] for _, pts in traces.values())
    span = t_end - t_begin
    t_from = a.from_s if a.from_s is not None else t_begin + a.frm * span
    t_until = a.until_s if a.until_s is not None else t_end
    if not t_begin <= t_from < t_until:
        p.error(f"--from-s {t_from:g} / --until-s {t_until:g}: need {t_begin:g} <= FROM < UNTIL")
    a.frm = (t_from - t_begin) / span
    data_span = t_until - t_from
    data_h = a.data_hours if a.data_hours is not None else 24 * (1 - a.frm)
    print(f"trace {a.rss_tsv}: {span:.0f} s wall, {len(traces)} processes; flat = growth from "
          f"t = {t_from:.0f} s ({100 * a.frm:.1f} % of the run) to t = {t_until:.0f} s "
          f"<= {a.bound_mb:g} MB")
    print(f"\n| process | pid | RSS at {100 * a.frm:.1f} % [MB] | peak [MB] | growth after it [MB] "
          f"| RSS at {t_until:.0f} s [MB] | slope after it [MB per data hour] | flat |")
    print("|---|---|---|---|---|---|---|---|")
    all_flat = True
    for pid, (name, pts) in sorted(traces.items(), key=lambda kv: kv[1][0]):
        after = [(t, kb) for t, kb in pts if t_from <= t <= t_until]
        if not after or pts[0][0] > t_from:
            print(f"| {name} | {pid} | (not alive at {100 * a.frm:.1f} %: {pts[0][0]:.0f}-"
                  f"{pts[-1][0]:.0f} s) | {max(k for _, k in pts) / 1024:.1f} | | | | |")
            continue
        at_kb = after[0][1]
        growth_mb = (max(k for _, k in after) - at_kb) / 1024
        slope = slope_kb_per_s(after) * data_span / data_h / 1024 if data_h > 0 else 0.0
        flat = growth_mb <= a.bound_mb
        all_flat &= flat
        print(f"| {name} | {pid} | {at_kb / 1024:.1f} | {max(k for _, k in pts) / 1024:.1f} | "
              f"{growth_mb:+.1f} | {after[-1][1] / 1024:.1f} | {slope:+.3f} | "
              f"{'yes' if flat else 'NO'} |")
    print(f"\nevery process alive at {100 * a.frm:.1f} % flat within {a.bound_mb:g} MB: "
          f"{'yes' if all_flat else 'no'}")
    return 0 if all_flat else 1


if __name__ == "__main__":
    sys.exit(main())

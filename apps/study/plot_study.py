#!/usr/bin/env python3
"""Plots of a glossyhr study (called by `glossyhr study`): relative RMSE against solve time and against
peak memory, log-log, one line per method and basis (points along a line differ in the other grid
keys, sorted by time), the path tracer's own curve on the time plot. matplotlib because Debian
packages it (python3-matplotlib) and it writes PNGs without a display (Agg backend)."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def series(rows, x_key):
    lines = defaultdict(list)
    for r in rows:
        if r["kind"] != "solve" or r["status"].startswith("failed") or not r["rel_rmse"] or not r[x_key]:
            continue
        method = r.get("algorithm", "diffuse")
        for k in ("iteration", "basis", "host"):
            if r.get(k):
                method += " " + r[k]
        lines[method].append((float(r[x_key]), float(r["rel_rmse"]), r["camera"]))
    return lines


def main(csv_path, time_png, memory_png):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    cameras = sorted({r["camera"] for r in rows if r["camera"]})
    for png, x_key, xlabel in ((time_png, "seconds", "solve time (s, wall)"),
                               (memory_png, "peak_rss_mb", "peak memory (MiB, RSS)")):
        fig, ax = plt.subplots(figsize=(7, 5))
        for method, pts in sorted(series(rows, x_key).items()):
            for cam in cameras:
                p = sorted((x, y) for x, y, c in pts if c == cam)
                if p:
                    ax.plot([x for x, _ in p], [y for _, y in p], "o-",
                            label=method + (" / " + cam if len(cameras) > 1 else ""))
        if x_key == "seconds":
            for cam in cameras:
                p = sorted((float(r["seconds"]), float(r["rel_rmse"])) for r in rows
                           if r["kind"] == "path_tracer" and r["camera"] == cam and r["rel_rmse"] and r["seconds"])
                if p:
                    ax.plot([x for x, _ in p], [y for _, y in p], "k--s",
                            label="path tracer" + (" / " + cam if len(cameras) > 1 else ""))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("relative RMSE of luminance vs reference (lights left out)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(png, dpi=100)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: plot_study.py study.csv error_vs_time.png error_vs_memory.png")
    main(*sys.argv[1:])

#!/usr/bin/env python3
"""Both hosts on the same scenes, one run each (issue 14): initial patches, final elements and
leaves, links stored and computed, rays, time (and the visibility share), peak RSS, energy balance.

Each solve is its own `glossyhr solve` process, so peak RSS is that run's alone (stats.json reads it
from getrusage). One run per row: absolute times drift on these shared machines, so read the two
hosts' times as a ratio measured minutes apart, not as a benchmark of record.

  bench/bench_hosts.py GLOSSYHR [--scene FILE ...] [--threads N] [--timeout S] [--json OUT]
Default scenes: scenes/soda.json and scenes/mgf/soda.mgf (the Soda Shoppe), the Cornell box.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

HOSTS = ["bright", "vision"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENES = ["scenes/soda.json", "scenes/mgf/soda.mgf", "scenes/cornell_box.json"]


def run(glossyhr, scene, host, threads, timeout, extra):
    with tempfile.TemporaryDirectory(prefix="bench_hosts_") as out:
        cmd = [glossyhr, "solve", scene, "--host", host, "--quiet", "-o", out, "--threads", str(threads)] + extra
        t0 = time.monotonic()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"scene": scene, "host": host, "error": "timeout after %d s" % timeout}
        wall = time.monotonic() - t0
        stats = os.path.join(out, "stats.json")
        if p.returncode not in (0, 3) or not os.path.exists(stats):
            return {"scene": scene, "host": host, "error": "exit %d: %s" % (p.returncode, p.stderr.strip()[-300:])}
        with open(stats) as f:
            j = json.load(f)
    c, e, ph = j["counts"], j["energy"], j["phases"]
    emitted = e["emitted_w"][1]
    balance = e["imbalance_w"][1] / emitted if emitted else float("nan")
    total = j["time_s"]["total"]
    return {
        "scene": scene, "host": host, "initial_patches": c["initial_patches"], "elements": c["elements"],
        "leaves": c["leaves"], "links_stored": c["links"], "links_computed": c.get("links_computed"),
        "rays": c["rays"], "time_s": total, "process_s": wall,
        "visibility_share": ph["visibility"]["wall_s"] / total if total else 0.0,
        "peak_rss_mb": j["memory_bytes"]["peak_rss"] / 2**20, "balance_pct": 100.0 * balance,
        "converged": j.get("converged"), "iterations": j.get("iterations"),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("glossyhr")
    ap.add_argument("--scene", action="append", help="scene file (repeatable)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=3600, help="seconds per run")
    ap.add_argument("--json", help="write the rows here too")
    ap.add_argument("extra", nargs="*", help="more solve flags after --, e.g. -- --eps 1e-3")
    a = ap.parse_args()
    scenes = a.scene or [os.path.join(ROOT, s) for s in DEFAULT_SCENES]
    rows = []
    cols = ["initial_patches", "elements", "leaves", "links_stored", "links_computed", "rays", "time_s",
            "visibility_share", "peak_rss_mb", "balance_pct", "iterations", "converged"]
    print("| scene | host | " + " | ".join(cols) + " |")
    print("|" + "---|" * (len(cols) + 2))
    for s in scenes:
        for h in HOSTS:
            r = run(a.glossyhr, s, h, a.threads, a.timeout, a.extra)
            rows.append(r)
            name = os.path.relpath(s, ROOT)
            if "error" in r:
                print("| %s | %s | %s |" % (name, h, r["error"]))
            else:
                cells = []
                for k in cols:
                    v = r[k]
                    cells.append("%.3g" % v if isinstance(v, float) else str(v))
                print("| %s | %s | %s |" % (name, h, " | ".join(cells)))
            sys.stdout.flush()
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()

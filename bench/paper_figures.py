#!/usr/bin/python3
"""The paper's Figures 1 and 3-6 re-created with our solver beside our path tracer (docs/results.md).

Every figure is made from runs of the `glossyhr` binary in this one invocation (or reused from the work
folder when their outputs are already there, so a figure can be remade without solving again):
  Fig. 1  empty Soda Shoppe room, glossy floor: Radiance Clustering with the non-adaptive tetrahedron
          against the adaptive Haar basis at max levels 3 and 4, beside the reference.
  Fig. 3  the Illumination Samples test scenes: three lights, glossy sphere, simple soda.
  Fig. 4  reference against IS for three lights and the glossy sphere, with times.
  Fig. 5  the same for the simple soda.
  Fig. 6  the full glossy Soda Shoppe (--with-soda; about 12 minutes on 2 cores).
Images are each solve's and each reference's own PNG: both are exposed by the same rule (0.18 over the
image's log-average luminance), so equal light gives equal pixels. Errors are `glossyhr compare`'s
relative RMSE of luminance, the lights left out and the reference's own noise taken out (a range).
Plots need matplotlib (Debian's python3-matplotlib), as the study command's do.

  bench/paper_figures.py --glossyhr build/ci/apps/glossyhr --work /tmp/figs --img docs/img \
      [--reference three_lights=DIR ...] [--spp 1024] [--with-soda]
"""
import argparse
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene_path(name):
    return os.path.join(ROOT, "scenes", name + ".json")


def camera_of(name):
    with open(scene_path(name)) as f:
        return json.load(f)["cameras"][0]["name"]


def run(args, cmd, out_dir):
    """Runs one glossyhr command into out_dir unless its stats.json is already there."""
    if os.path.exists(os.path.join(out_dir, "stats.json")):
        return
    full = [args.glossyhr] + cmd + ["-o", out_dir, "--quiet"]
    print("+", " ".join(full), file=sys.stderr, flush=True)
    r = subprocess.run(full, stdout=sys.stderr)
    if r.returncode not in (0, 3):  # 3: solved, but the energy audit disagrees (reported in the figure)
        sys.exit("failed (%d): %s" % (r.returncode, " ".join(full)))


def solve(args, name, tag, extra):
    d = os.path.join(args.work, name + "_" + tag)
    run(args, ["solve", scene_path(name), "--threads", str(args.threads)] + extra, d)
    with open(os.path.join(d, "stats.json")) as f:
        st = json.load(f)
    return d, st["time_s"]["total"]


def reference(args, name):
    if name in args.refs:
        return args.refs[name]
    d = os.path.join(args.work, name + "_reference")
    run(args, ["reference", scene_path(name), "--spp", str(args.spp), "--threads", str(args.threads)], d)
    return d


def compare(args, name, sol_dir, ref_dir):
    cam = camera_of(name)
    out = subprocess.run(
        [args.glossyhr, "compare", os.path.join(sol_dir, cam + ".exr"), os.path.join(ref_dir, cam + ".exr"),
         "--exclude-lights", scene_path(name), "--reference-variance", os.path.join(ref_dir, cam + ".var.exr"),
         "-o", os.path.join(sol_dir, "difference.png"), "--json"], capture_output=True, text=True, check=True)
    m = json.loads(out.stdout)
    lo, hi = m["rel_rmse_reference_noise_removed"]
    return lo, hi, m["mean_ratio"]


def ref_seconds(ref_dir):
    with open(os.path.join(ref_dir, "stats.json")) as f:
        st = json.load(f)
    return sum(c["time_s"] for c in st["cameras"])


def panel(ax, png, title):
    ax.imshow(mpimg.imread(png))
    ax.set_title(title, fontsize=8)
    ax.axis("off")


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=60)
    plt.close(fig)
    print("wrote", path, file=sys.stderr)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--glossyhr", required=True)
    p.add_argument("--work", required=True, help="folder for the runs (kept: a second call reuses them)")
    p.add_argument("--img", required=True, help="folder for the figures (docs/img)")
    p.add_argument("--reference", action="append", default=[], help="SCENE=DIR: an existing reference run")
    p.add_argument("--spp", type=int, default=1024, help="samples per pixel of references made here")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--room-eps", default="1e-3", help="spatial threshold of Figure 1's runs")
    p.add_argument("--with-soda", action="store_true", help="also Figure 6, the full glossy Soda Shoppe")
    args = p.parse_args()
    args.refs = dict(r.split("=", 1) for r in args.reference)
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.img, exist_ok=True)
    rows = []

    # Figures 3-5: Illumination Samples at the defaults against the reference.
    scenes = ["three_lights", "glossy_sphere", "simple_soda"]
    res = {}
    for name in scenes:
        d, t = solve(args, name, "is", ["--algorithm", "is"])
        r = reference(args, name)
        res[name] = (d, t, r, ref_seconds(r)) + compare(args, name, d, r)
        rows.append((name, "IS, defaults", t) + res[name][4:])
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.3))
    for ax, name in zip(axes, scenes):
        d, t = res[name][0], res[name][1]
        panel(ax, os.path.join(d, camera_of(name) + ".png"), "%s: IS, %.1f s" % (name.replace("_", " "), t))
    save(fig, os.path.join(args.img, "fig3_is_scenes.png"))
    for fname, group in (("fig4_reference_vs_is.png", scenes[:2]), ("fig5_simple_soda.png", scenes[2:])):
        fig, axes = plt.subplots(len(group), 3, figsize=(12, 3.3 * len(group)), squeeze=False)
        for row, name in zip(axes, group):
            d, t, r, rt, lo, hi, mr = res[name]
            cam = camera_of(name)
            panel(row[0], os.path.join(r, cam + ".png"), "%s: path tracer, %.0f s" % (name.replace("_", " "), rt))
            panel(row[1], os.path.join(d, cam + ".png"), "IS solve %.1f s: rel. RMSE %.3f-%.3f, mean %.3f" % (t, lo, hi, mr))
            panel(row[2], os.path.join(d, "difference.png"), "difference (red: IS brighter; +-25 % of mean)")
        save(fig, os.path.join(args.img, fname))

    # Figure 1: RC on the empty room, non-adaptive tetrahedron against adaptive Haar, levels 3 and 4.
    room = "soda_room"
    r = reference(args, room)
    runs = []
    for level in (3, 4):
        for basis, extra in (("N/A tetra", ["--basis", "tetra", "--tetra-level", str(level)]),
                             ("Haar", ["--dir-max-level", str(level)])):
            tag = "rc_%s_%d" % (basis.split()[-1].lower(), level)
            d, t = solve(args, room, tag, ["--algorithm", "rc", "--eps", args.room_eps] + extra)
            lo, hi, mr = compare(args, room, d, r)
            runs.append((basis, level, d, t, lo, hi, mr))
            rows.append((room, "RC %s, max level %d, eps %s" % (basis, level, args.room_eps), t, lo, hi, mr))
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.6))
    cam = camera_of(room)
    panel(axes[0][0], os.path.join(r, cam + ".png"), "path tracer, %.0f s" % ref_seconds(r))
    axes[1][0].axis("off")
    for i, (basis, level, d, t, lo, hi, mr) in enumerate(runs):
        ax = axes[level - 3][1 + (basis == "Haar")]
        panel(ax, os.path.join(d, cam + ".png"), "RC %s, max level %d: %.0f s, rel. RMSE %.3f-%.3f" % (basis, level, t, lo, hi))
    save(fig, os.path.join(args.img, "fig1_tetra_vs_haar.png"))

    # Figure 6: the full glossy Soda Shoppe.
    if args.with_soda:
        d, t = solve(args, "soda", "is", ["--algorithm", "is"])
        with open(os.path.join(d, "stats.json")) as f:
            st = json.load(f)
        fig, ax = plt.subplots(1, 1, figsize=(6, 4.6))
        panel(ax, os.path.join(d, camera_of("soda") + ".png"),
              "glossy Soda Shoppe, IS: %.0f s, %s elements" % (t, st.get("counts", {}).get("elements", "?")))
        save(fig, os.path.join(args.img, "fig6_glossy_soda.png"))
        rows.append(("soda", "IS, defaults", t, float("nan"), float("nan"), float("nan")))

    print("| scene | run | solve s | rel. RMSE (reference noise out) | mean ratio |")
    print("|---|---|---|---|---|")
    for name, what, t, lo, hi, mr in rows:
        print("| %s | %s | %.1f | %.3f-%.3f | %.3f |" % (name, what, t, lo, hi, mr))


if __name__ == "__main__":
    main()

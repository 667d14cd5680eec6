#!/usr/bin/env python3
# `glossyhr reference` against Mitsuba 3's `path` integrator on the same diffuse scenes, in one run:
# per-sample time, variance per sample and time to a relative RMSE of 0.10 and 0.05, each as a ratio
# ours / Mitsuba. Installs nothing: Mitsuba is used when `import mitsuba` works in the interpreter
# that runs this script (see docs/reference.md for the virtual environment), otherwise only ours is
# measured and the script says so.
#
# Both renderers see the same triangles (export_scene_mesh writes our tessellation as PLY), the same
# one-sided diffuse materials (a specular part is dropped: Mitsuba's `diffuse` has none), the same
# pinhole camera with a box pixel filter, the same longest path (our bounces + 1 = Mitsuba's
# max_depth) and the same thread count. Errors are `glossyhr compare`'s relative RMSE of luminance
# against one long reference of ours, fitted as error^2 = a + b / spp: b is the relative variance per
# sample, a the reference's own noise plus any bias; time to an error e = (b / (e^2 - bias^2)) spp
# times the time per sample. Runs of the two renderers alternate so that load from other processes
# falls on both; CPU time (all threads) is printed beside wall time because it is the steadier one.
#
# Usage: bench_reference_vs_mitsuba.py [--build build/ci] [--size 128] [--threads 2] [--ref-spp 8192]
#        [--spp 16,32,64,128,256] [--reps 2] [--level-spp 512] [--scenes cornell_box,three_lights] [--variant llvm_ad_rgb]
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = {"cornell_box": "scenes/cornell_box.json", "three_lights": "scenes/three_lights.json"}


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    return r.stdout


def diffuse_scene(src, size, dst):
    """Our scene with its first camera at `size` pixels wide and the specular parts dropped."""
    s = json.load(open(src))
    cam = dict(s["cameras"][0])
    cam["height"] = max(1, round(size * cam["height"] / cam["width"]))
    cam["width"] = size
    s["cameras"] = [cam]
    for m in s["materials"].values():
        m.pop("specular", None)
        m.pop("exponent", None)
    json.dump(s, open(dst, "w"), indent=1)
    return cam


class Ours:
    name = "ours"

    def __init__(self, args, scene_json, work):
        self.bin = os.path.join(args.build, "apps", "glossyhr")
        self.args, self.scene, self.work = args, scene_json, work

    def render(self, spp, seed, tag):
        out = os.path.join(self.work, "ours_" + tag)
        run([self.bin, "reference", self.scene, "--spp", str(spp), "--seed", str(seed), "--threads",
             str(self.args.threads), "--max-depth", str(self.args.max_depth), "-o", out, "--quiet"])
        cam = json.load(open(os.path.join(out, "stats.json")))["cameras"][0]
        return os.path.join(out, cam["name"] + ".exr"), cam["time_s"], cam["cpu_s"]


class Mitsuba:
    name = "mitsuba"
    max_lanes = 1 << 22  # samples per Mitsuba launch: a wavefront this size keeps memory modest

    def __init__(self, args, cam, mesh_dir, work):
        import drjit as dr
        import mitsuba as mi
        mi.set_variant(args.variant)
        if hasattr(dr, "set_thread_count"):
            dr.set_thread_count(args.threads)
        self.dr, self.mi, self.work = dr, mi, work
        self.pixels = cam["width"] * cam["height"]
        d = {"type": "scene",
             "integrator": {"type": "path", "max_depth": args.max_depth + 1},
             "sensor": {"type": "perspective", "fov": cam["fov_y_deg"], "fov_axis": "y",
                        "to_world": mi.ScalarTransform4f().look_at(origin=cam["eye"], target=cam["look_at"],
                                                                    up=cam.get("up", [0, 1, 0])),
                        "film": {"type": "hdrfilm", "width": cam["width"], "height": cam["height"],
                                 "rfilter": {"type": "box"}, "pixel_format": "rgb", "component_format": "float32"},
                        "sampler": {"type": "independent", "sample_count": 1}}}
        for m in json.load(open(os.path.join(mesh_dir, "materials.json"))):
            shape = {"type": "ply", "filename": os.path.join(mesh_dir, m["ply"]), "face_normals": True,
                     "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": m["diffuse"]}}}
            if max(m["emission"]) > 0:
                shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": m["emission"]}}
            d["shape_" + m["ply"].replace(".", "_")] = shape
        self.scene = self.mi.load_dict(d)
        self.compiled = set()
        self.jit_s = 0.0

    def _pass(self, spp, seed):
        t, c = time.perf_counter(), time.process_time()
        img = self.mi.render(self.scene, spp=spp, seed=seed)
        self.dr.eval(img)
        self.dr.sync_thread()
        return img, time.perf_counter() - t, time.process_time() - c

    def render(self, spp, seed, tag):
        per = max(1, min(spp, self.max_lanes // self.pixels))
        while spp % per:
            per -= 1
        if per not in self.compiled:
            # First launch of a wavefront size traces and JIT-compiles the kernels: its time minus a
            # second, cached launch is the compile cost, kept out of the rendering time.
            _, first, _ = self._pass(per, 2**31 - 1)
            _, again, _ = self._pass(per, 2**31 - 2)
            self.jit_s += max(0.0, first - again)
            self.compiled.add(per)
        acc, wall, cpu = None, 0.0, 0.0
        for k in range(spp // per):
            img, w, c = self._pass(per, seed * 100003 + k)
            acc = img if acc is None else acc + img
            wall, cpu = wall + w, cpu + c
        path = os.path.join(self.work, "mitsuba_%s.exr" % tag)
        self.mi.Bitmap(acc / float(spp // per)).write(path)
        return path, wall, cpu


def compare(args, a, b):
    out = run([os.path.join(args.build, "apps", "glossyhr"), "compare", a, b, "--json"])
    return json.loads(out)


def fit(points):
    """Least squares of error^2 = a + b / spp over (spp, error^2) points, each residual relative to
    its point (a squared error scatters in proportion to its size, so low-spp points would rule)."""
    s00 = s01 = s11 = r0 = r1 = 0.0
    for spp, e2 in points:
        w = 1.0 / (e2 * e2)
        x = 1.0 / spp
        s00, s01, s11, r0, r1 = s00 + w, s01 + w * x, s11 + w * x * x, r0 + w * e2, r1 + w * x * e2
    det = s00 * s11 - s01 * s01
    return (r0 * s11 - r1 * s01) / det, (s00 * r1 - s01 * r0) / det


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", default=os.path.join(ROOT, "build", "ci"))
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=64, help="our bounces; Mitsuba gets max_depth one more")
    p.add_argument("--ref-spp", type=int, default=8192)
    p.add_argument("--spp", default="16,32,64,128,256")
    p.add_argument("--reps", type=int, default=2, help="renders per spp level, at least")
    p.add_argument("--level-spp", type=int, default=512, help="samples per pixel per spp level, summed over renders")
    p.add_argument("--scenes", default="cornell_box,three_lights")
    p.add_argument("--variant", default="llvm_ad_rgb")
    p.add_argument("--work", default=None)
    args = p.parse_args()
    spps = [int(s) for s in args.spp.split(",")]
    # Dr.Jit's LLVM back end needs a recent libLLVM; Debian 12's default one is too old (docs/reference.md).
    for lib in ("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"):
        if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(lib):
            os.environ["DRJIT_LIBLLVM_PATH"] = lib
    try:
        import mitsuba  # noqa: F401
        have_mitsuba = True
    except ImportError:
        have_mitsuba = False
        print("mitsuba is not importable by %s: measuring only ours (docs/reference.md says how to install it)"
              % sys.executable)
    work = args.work or tempfile.mkdtemp(prefix="bench_ref_mi_")
    print("work folder %s; %d threads; %s spp, each level max(%d, %d / spp) seeds; long reference %d spp" %
          (work, args.threads, args.spp, args.reps, args.level_spp, args.ref_spp))
    summary = []
    for name in args.scenes.split(","):
        sdir = os.path.join(work, name)
        os.makedirs(sdir, exist_ok=True)
        scene_json = os.path.join(sdir, "scene.json")
        cam = diffuse_scene(os.path.join(ROOT, SCENES[name]), args.size, scene_json)
        ours = Ours(args, scene_json, sdir)
        renderers = [ours]
        if have_mitsuba:
            mesh = os.path.join(sdir, "mesh")
            run([os.path.join(args.build, "bench", "export_scene_mesh"), scene_json, mesh])
            renderers.append(Mitsuba(args, cam, mesh, sdir))
        print("\n## %s, %d x %d pixels" % (name, cam["width"], cam["height"]))
        ref, ref_wall, _ = ours.render(args.ref_spp, 999983, "reference")
        print("long reference (ours, %d spp): %.1f s" % (args.ref_spp, ref_wall))
        pts = {r.name: [] for r in renderers}
        wall = {r.name: 0.0 for r in renderers}
        cpu = {r.name: 0.0 for r in renderers}
        total = {r.name: 0 for r in renderers}
        ratio = {r.name: [] for r in renderers}
        for spp in spps:
            for rep in range(max(args.reps, args.level_spp // spp)):
                for r in renderers:
                    img, w, c = r.render(spp, 1 + rep + 10 * spp, "%d_%d" % (spp, rep))
                    m = compare(args, img, ref)
                    pts[r.name].append((spp, m["rel_rmse"] ** 2))
                    wall[r.name] += w
                    cpu[r.name] += c
                    total[r.name] += spp
                    if spp == spps[-1]:
                        ratio[r.name].append(m["mean_ratio"])
        res = {}
        for r in renderers:
            a, b = fit(pts[r.name])
            res[r.name] = dict(a=a, b=b, wall=wall[r.name] / total[r.name], cpu=cpu[r.name] / total[r.name],
                               ratio=sum(ratio[r.name]) / len(ratio[r.name]))
        floor = res["ours"]["b"] / args.ref_spp  # the long reference's own relative noise
        print("| renderer | s/spp wall | s/spp CPU | rel. var/sample b | a - ref. noise | mean ratio | "
              "t(0.10) wall | t(0.05) wall |")
        print("|---|---|---|---|---|---|---|---|")
        for r in renderers:
            x = res[r.name]
            bias2 = max(0.0, x["a"] - floor)
            for e in (0.10, 0.05):
                x["t%.2f" % e] = x["b"] / (e * e - bias2) * x["wall"] if e * e > bias2 else float("inf")
            print("| %s | %.4g | %.4g | %.4g | %.2g | %.4f | %.3g s | %.3g s |" %
                  (r.name, x["wall"], x["cpu"], x["b"], x["a"] - floor, x["ratio"], x["t0.10"], x["t0.05"]))
        if have_mitsuba:
            o, m = res["ours"], res["mitsuba"]
            line = (name, o["wall"] / m["wall"], o["cpu"] / m["cpu"], o["b"] / m["b"], o["t0.10"] / m["t0.10"],
                    o["t0.05"] / m["t0.05"], o["b"] * o["wall"] / (m["b"] * m["wall"]))
            summary.append(line)
            print("ours / Mitsuba: per-sample time %.2f (CPU %.2f), variance per sample %.2f, time to 0.10: %.2f, "
                  "time to 0.05: %.2f, noise alone (b x time): %.2f; Mitsuba JIT compile %.2f s (not counted)"
                  % (line[1:] + (renderers[1].jit_s,)))
    if summary:
        print("\nours / Mitsuba, ratios (below 1: ours is faster or less noisy)")
        print("| scene | per-sample time (wall) | (CPU) | variance per sample | time to 0.10 | time to 0.05 | "
              "noise alone (b x time) |")
        print("|---|---|---|---|---|---|---|")
        for s in summary:
            print("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |" % s)


if __name__ == "__main__":
    main()

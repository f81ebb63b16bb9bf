#!/usr/bin/env python3
"""scaling.py — how the cost of a frame grows with triangles and pixels (docs/performance.md,
"How cost grows").

Every row is real runs of `wavepath render ... --profile` (default estimator, depth 3):

  triangles: the built-in Cornell box (16,020), the staircase of ../shared/scenes (262,663;
             scenes/stress.json's 250,000-triangle mesh when the shared scenes are absent)
             and a procedural mesh of --big triangles (scenes/stress.json with the stress
             shape's count raised, written to a temporary JSON), all at 800x600;
  pixels:    the built-in box at 800x600 (0.48 Mpixel), 1600x1200 (1.92) and 3264x2448 (7.99).

Per row: the median over runs of the profile's median ms per spp (device span of a wave
over the passes it held), rays traced per spp (closest hit and shadow), Mrays/s = rays per
spp / ms per spp, ms per Mray, ns per pixel and spp, the BVH's build and flatten time, and
the device memory per group (render/memory.h) with bytes per triangle (BVH + scene) and
per path in flight. Prints a markdown table (and writes all figures as JSON with --json).

With --sweep, two more rows: the big row's stress mesh at 16,000 and 250,000 triangles, so
the cost against triangles can be read with the shape, camera and light fixed.

usage: scripts/scaling.py [--build build/release] [--spp 8] [--runs 1] [--big 2500000]
                          [--sweep] [--shared ../shared/scenes] [--json out.json]
                          [--only NAME ...]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MIB = 1024.0 * 1024.0


def run_render(binary, scene, size, spp, depth, workdir, label):
    prof = Path(workdir) / f"{label}.json"
    cmd = [str(binary), "render"] + ([scene] if scene else []) + [
        "--size", size, "--spp", str(spp), "--depth", str(depth), "-q",
        "-o", str(Path(workdir) / f"{label}.exr"), "--profile", str(prof)]
    t0 = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if r.returncode != 0:
        sys.exit(f"scaling.py: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    j = json.loads(prof.read_text())
    j["process_wall_s"] = wall
    return j


def row_figures(name, runs):
    """One table row from the profiles of several runs of one workload."""
    j = runs[-1]
    ms = statistics.median(r["median_ms_per_spp"] for r in runs)
    rays_per_spp = statistics.median(r["rays"] / r["spp"] for r in runs)
    closest_per_spp = statistics.median(r["rays_closest"] / r["spp"] for r in runs)
    m = j["memory"]
    g = m["groups"]
    pixels = j["settings"]["width"] * j["settings"]["height"]
    return {
        "workload": name,
        "triangles": j["scene"]["triangles"],
        "size": f'{j["settings"]["width"]}x{j["settings"]["height"]}',
        "pixels": pixels,
        "spp": j["spp"],
        "runs": len(runs),
        "median_ms_per_spp": ms,
        "all_ms_per_spp": [r["median_ms_per_spp"] for r in runs],
        "rays_per_spp": rays_per_spp,
        "closest_rays_per_spp": closest_per_spp,
        "mrays_per_s": rays_per_spp / (ms * 1e3),
        "ms_per_mray": ms / (rays_per_spp * 1e-6),
        "ns_per_pixel_spp": ms * 1e6 / pixels,
        "bvh_build_ms": statistics.median(r["scene"]["bvh_build_ms"] for r in runs),
        "bvh_flatten_ms": statistics.median(r["scene"]["bvh_flatten_ms"] for r in runs),
        "bvh_nodes": j["scene"]["bvh_nodes"],
        "mem_bvh": g["bvh"], "mem_scene": g["scene"], "mem_pool": g["pool"], "mem_film": g["film"],
        "mem_total": m["total_bytes"],
        "bytes_per_triangle": m["bytes_per_triangle"],
        "bvh_bytes_per_triangle": m["bvh_bytes_per_triangle"],
        "pool_paths": m["pool_paths"],
        "bytes_per_path": m["bytes_per_path"],
        "film_bytes_per_pixel": m["film_bytes_per_pixel"],
        "render_s": statistics.median(r["settings"]["render_s"] for r in runs),
        "process_wall_s": statistics.median(r["process_wall_s"] for r in runs),
    }


def table(rows):
    head = ("| workload | triangles | image | spp | ms/spp | Mrays/spp | Mrays/s | ms per Mray "
            "| ns per pixel·spp | BVH build + flatten ms | BVH MiB | scene MiB | B/triangle (BVH) "
            "| pool MiB (paths × B) | film MiB |")
    out = [head, "|" + "|".join(["---"] * (head.count("|") - 1)) + "|"]
    for r in rows:
        out.append(
            f'| {r["workload"]} | {r["triangles"]:,} | {r["size"]} ({r["pixels"] / 1e6:.2f} Mpx) '
            f'| {r["spp"]:g} | {r["median_ms_per_spp"]:.1f} | {r["rays_per_spp"] / 1e6:.2f} '
            f'| {r["mrays_per_s"]:.2f} | {r["ms_per_mray"]:.1f} | {r["ns_per_pixel_spp"]:.0f} '
            f'| {r["bvh_build_ms"]:.0f} + {r["bvh_flatten_ms"]:.0f} | {r["mem_bvh"] / MIB:.1f} '
            f'| {r["mem_scene"] / MIB:.1f} | {r["bytes_per_triangle"]:.0f} ({r["bvh_bytes_per_triangle"]:.0f}) '
            f'| {r["mem_pool"] / MIB:.0f} ({r["pool_paths"]:,} × {r["bytes_per_path"]}) '
            f'| {r["mem_film"] / MIB:.1f} |')
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "release"), help="build folder with wavepath")
    ap.add_argument("--spp", type=int, default=8, help="samples per pixel of each run (default 8)")
    ap.add_argument("--big-spp", type=int, default=4, help="spp of the 8-Mpixel row (default 4)")
    ap.add_argument("--runs", type=int, default=1, help="runs per row; the row takes their median")
    ap.add_argument("--depth", type=int, default=3)
    ap.add_argument("--big", type=int, default=2_500_000, help="triangles of the procedural mesh")
    ap.add_argument("--shared", default=os.environ.get("WP_SHARED_SCENES", str(ROOT.parent / "shared" / "scenes")),
                    help="the shared scenes folder (default ../shared/scenes, or $WP_SHARED_SCENES)")
    ap.add_argument("--json", help="also write every figure to this JSON file")
    ap.add_argument("--only", nargs="*", help="run only these workloads (names of the table)")
    ap.add_argument("--sweep", action="store_true",
                    help="also the stress mesh at 16k and 250k triangles (same shape as the big row)")
    a = ap.parse_args()
    binary = Path(a.build) / "wavepath"
    if not binary.exists():
        sys.exit(f"scaling.py: {binary} not found (build it: cmake --build --preset release --target wavepath)")

    with tempfile.TemporaryDirectory(prefix="wp-scaling-") as tmp:
        def stress_scene(triangles):
            """scenes/stress.json with its stress mesh at `triangles` (a temporary file)."""
            stress = json.loads((ROOT / "scenes" / "stress.json").read_text())
            for s in stress["shapes"]:
                if s["type"] == "stress":
                    s["triangles"] = triangles
            path = Path(tmp) / f"stress-{triangles}.json"
            path.write_text(json.dumps(stress))
            return str(path)
        staircase = Path(a.shared) / "staircase" / "scene-v4.pbrt"
        mid = ("staircase", str(staircase)) if staircase.exists() else ("stress.json", str(ROOT / "scenes" / "stress.json"))
        if not staircase.exists():
            print(f"scaling.py: {staircase} not found; using scenes/stress.json for the middle row",
                  file=sys.stderr)
        workloads = [
            ("built-in box", None, "800x600", a.spp),
            (mid[0], mid[1], "800x600", a.spp),
            (f"stress {a.big / 1e6:g}M", stress_scene(a.big), "800x600", a.spp),
            ("built-in box 2 Mpx", None, "1600x1200", a.spp),
            ("built-in box 8 Mpx", None, "3264x2448", a.big_spp),
        ]
        # The same shape at three tessellations: cost against triangles with the geometry,
        # the camera and the light fixed (--sweep).
        if a.sweep:
            workloads += [("stress 16k", stress_scene(16_000), "800x600", a.spp),
                          ("stress 250k", stress_scene(250_000), "800x600", a.spp)]
        rows = []
        for name, scene, size, spp in workloads:
            if a.only and name not in a.only:
                continue
            runs = []
            for k in range(a.runs):
                print(f"scaling.py: {name} {size} {spp} spp, run {k + 1}/{a.runs}", file=sys.stderr)
                runs.append(run_render(binary, scene, size, spp, a.depth, tmp, f"row{len(rows)}-{k}"))
            rows.append(row_figures(name, runs))
    load = os.getloadavg()
    print(table(rows))
    print(f"\nload average before the last row's end: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; "
          f"device: {runs[-1]['device']['name']}; depth {a.depth}, default estimator")
    if a.json:
        Path(a.json).write_text(json.dumps({"rows": rows, "loadavg": load}, indent=2) + "\n")


if __name__ == "__main__":
    main()

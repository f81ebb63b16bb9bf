#!/usr/bin/env python3
"""oidn_compare.py — wavepath's denoiser against Intel Open Image Denoise (OIDN), the
quality anchor of issue 16 (docs/denoise.md, "Against OIDN").

For each spp it renders SCENE with `wavepath render --denoise --aov albedo,normal` (the
denoised image, and the noisy one beside it with its albedo and normal channels), runs OIDN
(PyPI `pyoidn`, its bundled CPU library; filter "RT", HDR, quality high, albedo and normal
prefiltered by OIDN) on the noisy colour + albedo + normal, and measures the relMSE of the
noisy, the wavepath-denoised and the OIDN-denoised image against a reference with
`wavepath compare` (eps 1e-2). Prints a Markdown table and, with --csv, writes it as CSV.

Optional: needs `pip install pyoidn numpy OpenEXR` (no GPU); nothing in the build or CI
depends on it. Without them it says so and exits 77 (skipped).

Denoised images are biased: their relMSE is not a Monte Carlo error (docs/denoise.md).

usage: scripts/denoise/oidn_compare.py [--wavepath BIN] [--scene SCENE] [--size WxH]
           [--depth D] [--spp 4,16,64,256] [--seed S] [--reference REF.exr | --ref-spp N]
           [--out DIR] [--csv FILE]
Defaults: the built-in box at 64x48, depth 3, against tests/references/cornell-box.exr
(4096 spp, seed 1000).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def need_modules():
    try:
        import numpy  # noqa: F401
        import OpenEXR  # noqa: F401
        import pyoidn  # noqa: F401
    except ImportError as e:
        print(f"oidn_compare.py: skipped: {e.name} is not installed "
              "(pip install pyoidn numpy OpenEXR; optional, see docs/denoise.md)", file=sys.stderr)
        sys.exit(77)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"oidn_compare.py: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return r.stdout


def read_exr(path):
    import numpy as np
    import OpenEXR
    with OpenEXR.File(path, separate_channels=True) as f:
        ch = f.channels()

        def rgb(names):
            for n in names:
                if n not in ch:
                    sys.exit(f"oidn_compare.py: {path} has no channel {n} (has {sorted(ch)})")
            return np.ascontiguousarray(np.stack([ch[n].pixels for n in names], axis=-1), dtype=np.float32)

        return (rgb(["R", "G", "B"]), rgb(["albedo.R", "albedo.G", "albedo.B"]),
                rgb(["normal.X", "normal.Y", "normal.Z"]))


def write_exr(path, img):
    import OpenEXR
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    channels = {"R": img[..., 0].copy(), "G": img[..., 1].copy(), "B": img[..., 2].copy()}
    with OpenEXR.File(header, channels) as f:
        f.write(path)


def relmse(wavepath, image, reference):
    out = run([wavepath, "compare", image, reference])
    m = re.search(r"relMSE\s+([0-9.eE+-]+)", out)
    if not m:
        sys.exit(f"oidn_compare.py: no relMSE in `wavepath compare` output:\n{out}")
    return float(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wavepath", default=os.path.join(ROOT, "build", "release", "wavepath"))
    ap.add_argument("--scene", default="builtin:cornell-box")
    ap.add_argument("--size", default="64x48")
    ap.add_argument("--depth", type=int, default=3)
    ap.add_argument("--spp", default="4,16,64,256")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--reference", help="reference EXR of the same size (default: the stored box reference)")
    ap.add_argument("--ref-spp", type=int, help="render the reference with this many spp (seed 1000)")
    ap.add_argument("--out", default="oidn-compare")
    ap.add_argument("--csv")
    a = ap.parse_args()
    need_modules()
    import numpy as np
    import pyoidn

    if not os.access(a.wavepath, os.X_OK):
        sys.exit(f"oidn_compare.py: no wavepath binary at {a.wavepath} (build first, or --wavepath)")
    os.makedirs(a.out, exist_ok=True)
    common = [a.scene, "--size", a.size, "--depth", str(a.depth)]
    ref = a.reference
    if a.ref_spp:
        ref = os.path.join(a.out, "reference.exr")
        run([a.wavepath, "render", *common, "--spp", str(a.ref_spp), "--seed", "1000", "-q", "-o", ref])
    elif not ref:
        if a.scene != "builtin:cornell-box" or a.size != "64x48" or a.depth != 3:
            sys.exit("oidn_compare.py: give --reference or --ref-spp (the stored reference is the "
                     "built-in box at 64x48, depth 3)")
        ref = os.path.join(ROOT, "tests", "references", "cornell-box.exr")

    # Warm OIDN up (device and filter creation) so the timed calls are the filter alone.
    pyoidn.denoise(np.zeros((8, 8, 3), np.float32), np.zeros((8, 8, 3), np.float32),
                   np.zeros((8, 8, 3), np.float32), hdr=True)
    rows = []
    for spp in [int(s) for s in a.spp.split(",")]:
        out = os.path.join(a.out, f"spp{spp}.exr")
        prof = os.path.join(a.out, f"spp{spp}.json")
        run([a.wavepath, "render", *common, "--spp", str(spp), "--seed", str(a.seed), "--denoise",
             "--aov", "albedo,normal", "-q", "-o", out, "--profile", prof])
        noisy = os.path.join(a.out, f"spp{spp}.noisy.exr")
        with open(prof) as f:
            p = json.load(f)
        color, albedo, normal = read_exr(noisy)
        t = time.perf_counter()
        den = pyoidn.denoise(color, albedo, normal, hdr=True, quality="high")
        oidn_ms = (time.perf_counter() - t) * 1e3
        oidn_path = os.path.join(a.out, f"spp{spp}.oidn.exr")
        write_exr(oidn_path, den)
        rows.append({
            "spp": spp,
            "render_s": p["settings"]["render_s"],
            "noisy": relmse(a.wavepath, noisy, ref),
            "wavepath": relmse(a.wavepath, out, ref),
            "wavepath_ms": p["denoise"]["ms"],
            "oidn": relmse(a.wavepath, oidn_path, ref),
            "oidn_ms": oidn_ms,
        })
    print(f"{a.scene} {a.size}, depth {a.depth}, seed {a.seed}; reference {os.path.relpath(ref)}; "
          "relMSE (eps 1e-2); denoised images are biased")
    print("| spp | render s | noisy | wavepath-denoised | wavepath ms | OIDN | OIDN ms | wavepath / OIDN |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['spp']} | {r['render_s']:.2f} | {r['noisy']:.4g} | {r['wavepath']:.4g} | "
              f"{r['wavepath_ms']:.1f} | {r['oidn']:.4g} | {r['oidn_ms']:.1f} | "
              f"{r['wavepath'] / r['oidn']:.2f} |")
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("spp,render_s,relmse_noisy,relmse_wavepath,wavepath_ms,relmse_oidn,oidn_ms\n")
            for r in rows:
                f.write(f"{r['spp']},{r['render_s']},{r['noisy']},{r['wavepath']},{r['wavepath_ms']},"
                        f"{r['oidn']},{r['oidn_ms']}\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""plate_errors.py — relMSE per glossy plate of builtin:veach-plates (src/scene/builtin.cpp).

usage: plate_errors.py REF.exr IMG.exr [IMG.exr ...]

Labels every pixel by the plate its camera ray (through the pixel centre) hits first (the
inner 80% of each plate's depth, away from its edges), with
the scene's camera and plate geometry repeated here, and prints per image the relMSE
(mean over the plate's pixels and channels of (x - r)^2 / (r^2 + 1e-2), as `wavepath
compare`) on each plate (roughness alpha), and over the whole image. Pixels are read with
`oiiotool --dumpdata`.
"""
import subprocess
import sys

import numpy as np

ALPHAS = [0.30, 0.15, 0.07, 0.02]


def read_exr(path):
    out = subprocess.run(["oiiotool", "--dumpdata", path], check=True, capture_output=True,
                         text=True).stdout.splitlines()
    w, h = [int(v) for v in out[0].split(":")[1].split(",")[0].split("x")]
    px = np.array([[float(v) for v in line.split(":")[1].split()[:3]] for line in out[1:]
                   if line.strip().startswith("Pixel")])
    return px.reshape(h, w, 3)


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def plate_labels(w, h):
    cam, target, up = np.array([0.0, 2.0, 7.0]), np.array([0.0, 0.6, 0.0]), np.array([0.0, 1.0, 0.0])
    fwd = normalize(target - cam)
    right = normalize(np.cross(fwd, up))
    upv = np.cross(right, fwd)
    th = np.tan(np.radians(35.0) / 2)
    xs = (np.arange(w) + 0.5) / w * 2 - 1
    ys = 1 - (np.arange(h) + 0.5) / h * 2
    X, Y = np.meshgrid(xs, ys)
    d = fwd + X[..., None] * right * th * w / h + Y[..., None] * upv * th
    best_t = np.full((h, w), np.inf)
    label = np.full((h, w), -1)
    aim = np.array([0.0, 3.0, -3.0])
    ex = np.array([1.0, 0.0, 0.0])
    for k in range(4):
        c = np.array([0.0, 0.35 * k, 1.6 - 1.0 * k])
        n = normalize(normalize(cam - c) + normalize(aim - c))
        ev = 0.8 * normalize(np.cross(n, ex))
        denom = d @ n
        t = ((c - cam) @ n) / np.where(np.abs(denom) > 1e-12, denom, 1e-12)
        p = cam + t[..., None] * d - c
        inside = (np.abs(p @ ex) <= 3.0) & (np.abs(p @ ev) <= 0.8 * 0.4) & (t > 0)
        hit = inside & (t < best_t)
        best_t[hit] = t[hit]
        label[hit] = k
    return label


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref = read_exr(sys.argv[1])
    h, w, _ = ref.shape
    label = plate_labels(w, h)
    print("| image | " + " | ".join(f"plate α={a}" for a in ALPHAS) + " | whole image |")
    print("|---" * 6 + "|")
    for path in sys.argv[2:]:
        img = read_exr(path)
        err = (img - ref) ** 2 / (ref ** 2 + 1e-2)
        cols = [f"{err[label == k].mean():.3e}" for k in range(4)]
        print(f"| {path.split('/')[-1]} | " + " | ".join(cols) + f" | {err.mean():.3e} |")


if __name__ == "__main__":
    main()

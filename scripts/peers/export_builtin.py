#!/usr/bin/env python3
"""export_builtin.py — wavepath's built-in Cornell box (builtin:cornell-box) as files the peers read.

usage: export_builtin.py OUT_DIR [--width W --height H --depth D]

Writes into OUT_DIR:
  builtin-<material>.obj   one OBJ per material (Mitsuba loads each as a shape)
  builtin.obj              all of them, with `usemtl` groups (Cycles, through cycles_worker.py)
  builtin.xml              a Mitsuba 3 scene: the shapes, BSDFs, emitter and camera
  builtin.json             {"triangles", "camera", "materials"}: what time_to_error.py hands
                           to cycles_worker.py
and prints the triangle count (time_to_error.py checks it against wavepath's own count).

The geometry repeats src/scene/builtin.cpp (make_cornell_box(16000)) and the mesh builders of
src/scene/procedural.cpp step for step: five wall quads and the light quad, a tall box of
18 x 18 cells a face turned 17 degrees, a UV sphere with its analytic vertex normals. Keep the
two in step; a change there shows here as a triangle count that differs from wavepath's, or as
a wavepath error that stops falling with spp.

Materials, and how faithful each peer's version is:
  white, red, green   Lambertian                         exact in Mitsuba and Cycles
  light               emitter (17, 12, 4), front side     exact
  mirror              perfect mirror, albedo 0.9          exact (Mitsuba conductor "none",
                                                          Cycles Glossy Sharp)
  glossy              wavepath GLOSSY: GGX alpha = sqrt(2/102), Schlick Fresnel F0 = albedo,
                      height-correlated Smith G2.
                      Mitsuba: principled, metallic 1, base_color = albedo, roughness =
                      sqrt(alpha): the same D and Schlick Fresnel, but separable Smith G.
                      Cycles: Glossy BSDF GGX, colour = Schlick Fresnel of the shading
                      normal's angle (cycles_worker.py). Both approximations differ from
                      wavepath only near grazing angles.
"""
import argparse
import json
import math
import os

import numpy as np

WHITE, RED, GREEN = (0.725, 0.71, 0.68), (0.63, 0.065, 0.05), (0.14, 0.45, 0.091)
LIGHT = (17.0, 12.0, 4.0)
MIRROR = (0.9, 0.9, 0.9)
GLOSSY_ALPHA = math.sqrt(2.0 / (100.0 + 2.0))  # phong_exponent_to_alpha(100)


def lround(x):
    return int(math.floor(x + 0.5)) if x >= 0 else -int(math.floor(-x + 0.5))


def push_cell(tris, a, b, c, d):
    tris.append((a, b, c))
    tris.append((a, c, d))


def make_quad(corner, u, v):
    corner, u, v = (np.asarray(x, dtype=np.float64) for x in (corner, u, v))
    pos = [corner, corner + u, corner + v, corner + u + v]
    tris = []
    push_cell(tris, 0, 1, 3, 2)
    return pos, tris


def make_box(lo, hi, n):
    lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    s = n + 1
    ids, pos, tris = {}, [], []

    def vertex(i, j, k):
        key = (i, j, k)
        if key not in ids:
            ids[key] = len(pos)
            f = np.array([i, j, k], dtype=np.float64) / n
            p = lo + (hi - lo) * f
            for a, c in enumerate((i, j, k)):
                if c == n:
                    p[a] = hi[a]
            pos.append(p)
        return ids[key]

    for a in range(3):
        for side in range(2):
            u, v = (a + 1) % 3, (a + 2) % 3
            if side == 0:
                u, v = v, u
            c = 0 if side == 0 else n

            def at(su, sv, a=a, u=u, v=v, c=c):
                ijk = [0, 0, 0]
                ijk[a], ijk[u], ijk[v] = c, su, sv
                return vertex(*ijk)

            for sv in range(n):
                for su in range(n):
                    push_cell(tris, at(su, sv), at(su + 1, sv), at(su + 1, sv + 1), at(su, sv + 1))
    assert len(pos) <= s ** 3
    return pos, tris


def make_uv_sphere(center, radius, rings, segments):
    center = np.asarray(center, dtype=np.float64)
    pos = [center + np.array([0.0, radius, 0.0])]
    for r in range(1, rings):
        theta = math.pi * r / rings
        y, sr = math.cos(theta), math.sin(theta)
        for s in range(segments):
            phi = 2.0 * math.pi * s / segments
            pos.append(center + radius * np.array([sr * math.sin(phi), y, sr * math.cos(phi)]))
    south = len(pos)
    pos.append(center - np.array([0.0, radius, 0.0]))

    def vid(r, s):
        return 1 + (r - 1) * segments + s % segments

    tris = []
    for s in range(segments):
        tris.append((0, vid(1, s), vid(1, s + 1)))
        tris.append((south, vid(rings - 1, s + 1), vid(rings - 1, s)))
    for r in range(1, rings - 1):
        for s in range(segments):
            push_cell(tris, vid(r, s), vid(r + 1, s), vid(r + 1, s + 1), vid(r, s + 1))
    return pos, tris


def sphere_resolution(budget):
    r0 = max(3, lround(math.sqrt(budget / 4.0)))
    rings, segments, best = 3, 6, -1
    for r in range(max(3, r0 // 2), 2 * r0 + 1):
        s = max(3, lround(budget / (2.0 * (r - 1))))
        if 2 * s < 3 * r or 2 * s > 5 * r:
            continue
        err = abs(2 * s * (r - 1) - budget) * 1000 + abs(s - 2 * r)
        if best < 0 or err < best:
            best, rings, segments = err, r, s
    return rings, segments


def rotate_y(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def look_at(origin, target, up):
    """Mitsuba's look_at: columns (left, up, forward, origin), row-major 4x4 as a flat list."""
    o, t, u = (np.asarray(x, dtype=np.float64) for x in (origin, target, up))
    d = (t - o) / np.linalg.norm(t - o)
    left = np.cross(u, d)
    left /= np.linalg.norm(left)
    new_up = np.cross(d, left)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, new_up, d, o
    return [float(x) for x in m.reshape(-1)]


def build(object_triangles=16000):
    """[(material, positions, triangles, normals or None)] as make_cornell_box builds them."""
    ex, ey, ez = np.eye(3)
    parts = []

    def quad(corner, u, v, mat):
        p, t = make_quad(corner, u, v)
        parts.append((mat, p, t, None))

    quad((-1, 0, -1), 2 * ez, 2 * ex, "white")   # floor
    quad((-1, 2, -1), 2 * ex, 2 * ez, "white")   # ceiling
    quad((-1, 0, -1), 2 * ex, 2 * ey, "white")   # back wall
    quad((-1, 0, -1), 2 * ey, 2 * ez, "red")     # left wall
    quad((1, 0, -1), 2 * ez, 2 * ey, "green")    # right wall
    quad((-0.24, 1.98, -0.22), 0.47 * ex, 0.38 * ez, "light")
    n = max(1, lround(math.sqrt(object_triangles / 48.0)))
    rings, segments = sphere_resolution(max(12, object_triangles - 12 * n * n))
    p, t = make_box((-0.3, 0.0, -0.3), (0.3, 1.2, 0.3), n)
    rot, shift = rotate_y(17.0), np.array([-0.33, 0.0, -0.32])
    parts.append(("glossy", [rot @ q + shift for q in p], t, None))
    center = np.array([0.42, 0.401, 0.3])
    p, t = make_uv_sphere(center, 0.4, rings, segments)
    normals = [(q - center) / np.linalg.norm(q - center) for q in p]
    parts.append(("mirror", p, t, normals))
    return parts


def write_obj(path, groups):
    """groups: [(material, positions, triangles, normals)]; one `usemtl` each."""
    with open(path, "w") as f:
        f.write("# wavepath builtin:cornell-box, written by scripts/peers/export_builtin.py\n")
        base_v, base_n = 1, 1
        for mat, pos, tris, nrm in groups:
            f.write(f"o {mat}\nusemtl {mat}\n")
            for q in pos:
                f.write(f"v {q[0]:.9g} {q[1]:.9g} {q[2]:.9g}\n")
            if nrm is not None:
                for q in nrm:
                    f.write(f"vn {q[0]:.9g} {q[1]:.9g} {q[2]:.9g}\n")
                for a, b, c in tris:
                    f.write(f"f {a + base_v}//{a + base_n} {b + base_v}//{b + base_n} "
                            f"{c + base_v}//{c + base_n}\n")
                base_n += len(nrm)
            else:
                for a, b, c in tris:
                    f.write(f"f {a + base_v} {b + base_v} {c + base_v}\n")
            base_v += len(pos)


def rgb(c):
    return f"{c[0]:.9g}, {c[1]:.9g}, {c[2]:.9g}"


def export(out_dir, width=128, height=96, depth=64):
    os.makedirs(out_dir, exist_ok=True)
    parts = build()
    by_mat = {}
    for part in parts:
        by_mat.setdefault(part[0], []).append(part)
    for mat, groups in by_mat.items():
        write_obj(os.path.join(out_dir, f"builtin-{mat}.obj"), groups)
    write_obj(os.path.join(out_dir, "builtin.obj"), parts)
    triangles = sum(len(p[2]) for p in parts)

    camera = {"to_world": look_at((0, 1, 3.9), (0, 1, 0), (0, 1, 0)), "fov": 40.0,
              "fov_axis": "y"}
    bsdfs = {
        "white": f'<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="{rgb(WHITE)}"/></bsdf></bsdf>',
        "red": f'<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="{rgb(RED)}"/></bsdf></bsdf>',
        "green": f'<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="{rgb(GREEN)}"/></bsdf></bsdf>',
        "light": '<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0, 0, 0"/></bsdf></bsdf>',
        "mirror": f'<bsdf type="twosided"><bsdf type="conductor"><string name="material" value="none"/>'
                  f'<rgb name="specular_reflectance" value="{rgb(MIRROR)}"/></bsdf></bsdf>',
        "glossy": f'<bsdf type="principled"><rgb name="base_color" value="{rgb(WHITE)}"/>'
                  f'<float name="metallic" value="1"/><float name="roughness" value="{math.sqrt(GLOSSY_ALPHA):.9g}"/></bsdf>',
    }
    m = camera["to_world"]
    lines = [
        '<scene version="3.0.0">',
        f'  <integrator type="path"><integer name="max_depth" value="{depth + 1}"/></integrator>',
        '  <sensor type="perspective">',
        f'    <float name="fov" value="{camera["fov"]}"/><string name="fov_axis" value="y"/>',
        f'    <transform name="to_world"><matrix value="{" ".join(f"{x:.9g}" for x in m)}"/></transform>',
        '    <sampler type="independent"><integer name="sample_count" value="16"/></sampler>',
        f'    <film type="hdrfilm"><integer name="width" value="{width}"/><integer name="height" value="{height}"/>',
        '      <string name="pixel_format" value="rgb"/><rfilter type="box"/></film>',
        '  </sensor>',
    ]
    for mat in by_mat:
        obj = os.path.abspath(os.path.join(out_dir, f"builtin-{mat}.obj"))
        flat = "" if mat == "mirror" else '<boolean name="face_normals" value="true"/>'
        emitter = (f'<emitter type="area"><rgb name="radiance" value="{rgb(LIGHT)}"/></emitter>'
                   if mat == "light" else "")
        lines.append(f'  <shape type="obj"><string name="filename" value="{obj}"/>{flat}'
                     f'{bsdfs[mat]}{emitter}</shape>')
    lines.append("</scene>")
    with open(os.path.join(out_dir, "builtin.xml"), "w") as f:
        f.write("\n".join(lines) + "\n")

    materials = {
        "white": {"type": "diffuse", "color": WHITE},
        "red": {"type": "diffuse", "color": RED},
        "green": {"type": "diffuse", "color": GREEN},
        "light": {"type": "emitter", "radiance": LIGHT},
        "mirror": {"type": "mirror", "color": MIRROR},
        "glossy": {"type": "ggx_schlick", "f0": WHITE, "alpha": GLOSSY_ALPHA},
    }
    desc = {"triangles": triangles, "camera": camera, "materials": materials,
            "obj": os.path.abspath(os.path.join(out_dir, "builtin.obj")),
            "xml": os.path.abspath(os.path.join(out_dir, "builtin.xml"))}
    with open(os.path.join(out_dir, "builtin.json"), "w") as f:
        json.dump(desc, f, indent=1)
    return desc


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=96)
    ap.add_argument("--depth", type=int, default=64, help="wavepath depth (bounces); "
                    "the XML's max_depth is depth + 1")
    a = ap.parse_args()
    desc = export(a.out_dir, a.width, a.height, a.depth)
    print(f"{desc['triangles']} triangles; wrote {a.out_dir}/builtin.xml, builtin.obj, builtin.json")


if __name__ == "__main__":
    main()

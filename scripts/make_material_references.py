#!/usr/bin/env python3
"""make_material_references.py — the Mitsuba 3 references of tests/test_material_reference.cpp.

Issue 14, item 3: small per-material scenes that both Mitsuba 3 and wavepath's Mitsuba reader
read. Each scene is a row of four spheres of one material family over a grey floor, once under
a square area light (black background: `<group>-area`) and once under a constant environment
(Mitsuba's `constant` emitter, wavepath's background: `<group>-env`). Writes the XML files and
the one mesh they use into tests/scenes/materials/, renders each with Mitsuba 3 (scalar_rgb,
path tracer, box filter) into tests/references/materials/<scene>.exr (linear RGB mean) and
<scene>.var.exr (variance of that mean, from K independent seeds), and records Mitsuba's
version and the settings in tests/references/materials/mitsuba.json.

Run on purpose only (the tests never make a missing reference):
    python3 -m venv /work/venv-mitsuba && /work/venv-mitsuba/bin/pip install mitsuba numpy
    /work/venv-mitsuba/bin/python scripts/make_material_references.py               # all
    /work/venv-mitsuba/bin/python scripts/make_material_references.py --scenes-only
    /work/venv-mitsuba/bin/python scripts/make_material_references.py --only conductor-env --preview /tmp/p
    /work/venv-mitsuba/bin/python scripts/make_material_references.py --check-stats 256

Depth: Mitsuba's max_depth N counts path segments; wavepath's reader makes it N − 1 bounces
(see make_appearance_references.py). Every scene here has max_depth 8.

Spheres: Mitsuba's analytic `sphere` (wavepath: a 5,120-triangle icosphere of the same area
with exact normals), except the anisotropic ones. Mitsuba's frame on a triangle mesh is the
shading normal with s along dp/du (on a mesh without uvs: the barycentric dp/du = p1 − p0,
which depends on the vertex order), wavepath's the Duff et al. frame of the shading normal
(Mitsuba's coordinate_system). So the anisotropic spheres are a flat-shaded icosphere whose
every face carries its own uvs, u = p·s, v = p·t with (s, t) = coordinate_system(face
normal): there dp/du = s exactly, and both renderers put α_u along the same axis.
"""
import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import appearance_assets as A  # noqa: E402
import make_appearance_references as R  # noqa: E402  (XML helpers, rendering, statistics)

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "tests" / "scenes" / "materials"
REFS = ROOT / "tests" / "references" / "materials"

SEEDS = 32
REF_SPP = 2048          # per scene, in all (SEEDS partial renders)
WIDTH, HEIGHT = 96, 48
MAX_DEPTH = 8
RADIUS = 0.4
XS = (-1.5, -0.5, 0.5, 1.5)
FLOOR_Y = -0.42
ANISO_MESH = "meshes/icosphere-aniso.ply"
AREA_RADIANCE = 6.0
ENV_RADIANCE = (0.6, 0.7, 0.9)


# --------------------------------------------------------------------------- the mesh

def coordinate_system(n):
    """Mitsuba 3's coordinate_system (Duff et al. 2017): (s, t) with (s, t, n) orthonormal."""
    sign = math.copysign(1.0, n[2])
    a = -1.0 / (sign + n[2])
    b = n[0] * n[1] * a
    s = np.array([1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]])
    t = np.array([b, sign + n[1] * n[1] * a, -n[1]])
    return s, t


def icosphere(subdivisions):
    """Unit icosphere, counter-clockwise seen from outside: positions, triangles."""
    p = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p),
             (0, -1, -p), (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    verts = [np.array(v, float) / np.linalg.norm(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                m = verts[i] + verts[j]
                verts.append(m / np.linalg.norm(m))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return np.array(verts), faces


def write_aniso_sphere(path):
    """A flat icosphere (320 faces, unshared vertices, no normals) turned by a fixed generic
    rotation (so that no face normal lies near z = 0, where coordinate_system switches
    branches), with per-face uvs u = p·s, v = p·t, (s, t) = coordinate_system(face normal)."""
    pos, faces = icosphere(2)
    rot = A.rotation_matrix((0.3, 0.8, 0.5), 23.0) @ A.rotation_matrix((1, 0, 0), 11.0)
    pos = pos @ rot.T
    out_p, out_uv, out_f = [], [], []
    min_nz = 1.0
    for a, b, c in faces:
        p0, p1, p2 = (pos[i].astype(np.float32).astype(np.float64) for i in (a, b, c))
        n = np.cross(p1 - p0, p2 - p0)
        n /= np.linalg.norm(n)
        assert np.dot(n, p0 + p1 + p2) > 0.0, "face wound inward"
        min_nz = min(min_nz, abs(n[2]))
        s, t = coordinate_system(n)
        k = len(out_p)
        for q in (p0, p1, p2):
            out_p.append(q)
            out_uv.append((np.dot(q, s), np.dot(q, t)))
        out_f.append((k, k + 1, k + 2))
    assert min_nz > 1e-3, f"a face normal has |z| = {min_nz}"
    path.parent.mkdir(parents=True, exist_ok=True)
    A.write_ply(path, out_p, out_f, None, out_uv)


# --------------------------------------------------------------------------- materials

def rgb(name, v):
    return R.rgb(name, v)


def flt(name, v):
    return f'<float name="{name}" value="{A.fmt(v)}"/>'


def string(name, v):
    return f'<string name="{name}" value="{v}"/>'


def bsdf(kind, *props):
    return f'<bsdf type="{kind}">' + "".join(props) + "</bsdf>"


ETA_K = (rgb("eta", (1.2, 0.9, 0.45)), rgb("k", (2.6, 3.0, 3.6)))

# Per group: four (description, BSDF XML, anisotropic mesh?) — one per sphere, left to right.
GROUPS = {
    "conductor": [
        ("conductor Au (named)", bsdf("conductor", string("material", "Au")), False),
        ("conductor eta/k, specular_reflectance (0.9, 0.8, 1)",
         bsdf("conductor", *ETA_K, rgb("specular_reflectance", (0.9, 0.8, 1.0))), False),
        ("roughconductor Cu beckmann alpha_u 0.05 alpha_v 0.3 (flat mesh)",
         bsdf("roughconductor", string("material", "Cu"), string("distribution", "beckmann"),
              flt("alpha_u", 0.05), flt("alpha_v", 0.3)), True),
        ("roughconductor eta/k ggx alpha_u 0.3 alpha_v 0.05 (flat mesh)",
         bsdf("roughconductor", *ETA_K, string("distribution", "ggx"),
              flt("alpha_u", 0.3), flt("alpha_v", 0.05)), True),
    ],
    "roughconductor": [
        ("roughconductor Al beckmann 0.1", bsdf("roughconductor", string("material", "Al"),
                                                flt("alpha", 0.1)), False),
        ("roughconductor Au beckmann 0.3", bsdf("roughconductor", string("material", "Au"),
                                                string("distribution", "beckmann"),
                                                flt("alpha", 0.3)), False),
        ("roughconductor Cu ggx 0.1", bsdf("roughconductor", string("material", "Cu"),
                                           string("distribution", "ggx"), flt("alpha", 0.1)), False),
        ("roughconductor eta/k ggx 0.3, specular_reflectance 0.7",
         bsdf("roughconductor", *ETA_K, string("distribution", "ggx"), flt("alpha", 0.3),
              rgb("specular_reflectance", 0.7)), False),
    ],
    "dielectric": [
        ("dielectric bk7 / air (defaults)", bsdf("dielectric"), False),
        ("dielectric water, specular_transmittance (0.95, 0.75, 0.55)",
         bsdf("dielectric", string("int_ior", "water"),
              rgb("specular_transmittance", (0.95, 0.75, 0.55))), False),
        ("dielectric 1.8, specular_reflectance 0.5",
         bsdf("dielectric", flt("int_ior", 1.8), flt("ext_ior", 1.0),
              rgb("specular_reflectance", 0.5)), False),
        ("dielectric 1.33 in 1.5 (eta < 1)",
         bsdf("dielectric", flt("int_ior", 1.33), flt("ext_ior", 1.5)), False),
    ],
    "roughdielectric": [
        ("roughdielectric bk7 beckmann 0.1", bsdf("roughdielectric", flt("alpha", 0.1)), False),
        ("roughdielectric water ggx 0.3, specular_transmittance (0.95, 0.75, 0.55)",
         bsdf("roughdielectric", string("int_ior", "water"), string("distribution", "ggx"),
              flt("alpha", 0.3), rgb("specular_transmittance", (0.95, 0.75, 0.55))), False),
        ("roughdielectric 1.7 beckmann 0.3, specular_reflectance 0.5",
         bsdf("roughdielectric", flt("int_ior", 1.7), flt("ext_ior", 1.0),
              string("distribution", "beckmann"), flt("alpha", 0.3),
              rgb("specular_reflectance", 0.5)), False),
        ("roughdielectric bk7 ggx alpha_u 0.05 alpha_v 0.3 (flat mesh)",
         bsdf("roughdielectric", string("distribution", "ggx"), flt("alpha_u", 0.05),
              flt("alpha_v", 0.3)), True),
    ],
    "thindielectric": [
        ("thindielectric bk7 (defaults)", bsdf("thindielectric"), False),
        ("thindielectric water, specular_transmittance (0.95, 0.75, 0.55)",
         bsdf("thindielectric", string("int_ior", "water"),
              rgb("specular_transmittance", (0.95, 0.75, 0.55))), False),
        ("thindielectric 2.0, specular_reflectance 0.6",
         bsdf("thindielectric", flt("int_ior", 2.0), flt("ext_ior", 1.0),
              rgb("specular_reflectance", 0.6)), False),
        ("thindielectric 1.4, specular_transmittance 0.5",
         bsdf("thindielectric", flt("int_ior", 1.4), flt("ext_ior", 1.0),
              rgb("specular_transmittance", 0.5)), False),
    ],
    "plastic": [
        ("plastic (defaults: diffuse 0.5, polypropylene)", bsdf("plastic"), False),
        ("plastic red, int_ior 1.6", bsdf("plastic", rgb("diffuse_reflectance", (0.8, 0.15, 0.1)),
                                         flt("int_ior", 1.6)), False),
        ("plastic blue, nonlinear", bsdf("plastic", rgb("diffuse_reflectance", (0.1, 0.3, 0.8)),
                                         '<boolean name="nonlinear" value="true"/>'), False),
        ("plastic green, specular_reflectance 0.4",
         bsdf("plastic", rgb("diffuse_reflectance", (0.2, 0.6, 0.15)),
              rgb("specular_reflectance", 0.4)), False),
    ],
    "roughplastic": [
        ("roughplastic red beckmann 0.1",
         bsdf("roughplastic", rgb("diffuse_reflectance", (0.8, 0.15, 0.1)), flt("alpha", 0.1)), False),
        ("roughplastic blue ggx 0.3, nonlinear",
         bsdf("roughplastic", rgb("diffuse_reflectance", (0.1, 0.3, 0.8)),
              string("distribution", "ggx"), flt("alpha", 0.3),
              '<boolean name="nonlinear" value="true"/>'), False),
        ("roughplastic defaults (diffuse 0.5, polypropylene, beckmann), alpha 0.3",
         bsdf("roughplastic", flt("alpha", 0.3)), False),
        ("roughplastic green ggx 0.05, int_ior 1.7, specular_reflectance 0.5",
         bsdf("roughplastic", rgb("diffuse_reflectance", (0.2, 0.6, 0.15)),
              string("distribution", "ggx"), flt("alpha", 0.05), flt("int_ior", 1.7),
              rgb("specular_reflectance", 0.5)), False),
    ],
}

LIGHTS = ("area", "env")


# --------------------------------------------------------------------------- the scenes

def sphere_shape(x, material, aniso):
    if aniso:
        return R.shape("ply", f'<scale value="{RADIUS}"/><translate x="{x}"/>', material,
                       f'<string name="filename" value="{ANISO_MESH}"/>'
                       '<boolean name="face_normals" value="true"/>')
    return (f'    <shape type="sphere">\n        <point name="center" x="{x}" y="0" z="0"/>\n'
            f'        <float name="radius" value="{RADIUS}"/>\n        {material}\n    </shape>')


def scene(group, light):
    spheres = GROUPS[group]
    parts = [
        R.integrator(MAX_DEPTH),
        R.sensor("0, 1, 5.5", "0, -0.05, 0", 41, WIDTH, HEIGHT),
        # The floor: 12 x 12, grey, two-sided
        R.shape("rectangle", f'<scale value="6"/><rotate x="1" angle="-90"/><translate y="{FLOOR_Y}"/>',
                R.diffuse(rgb("reflectance", 0.5))),
    ]
    if light == "area":
        # A 3 x 3 square up-left-front, facing the spheres' centre (large, so that the
        # caustics of the smooth spheres on the floor stay within reach of BSDF sampling)
        parts.append(R.shape("rectangle",
                             '<scale value="1.5"/><lookat origin="-2, 3, 3" target="0, 0, 0" up="0, 1, 0"/>',
                             R.black(), R.area(AREA_RADIANCE)))
    else:
        parts.append(f'    <emitter type="constant">{rgb("radiance", ENV_RADIANCE)}</emitter>')
    for x, (_, material, aniso) in zip(XS, spheres):
        parts.append(sphere_shape(x, material, aniso))
    lit = (f"a 3 x 3 area light of radiance {AREA_RADIANCE} up-left-front, black background"
           if light == "area" else f"a constant environment of radiance {ENV_RADIANCE}")
    names = "\n       ".join(f"{i + 1}. {d}" for i, (d, _, _) in enumerate(spheres))
    xml = R.scene_xml(f"""{group} under {lit}; four spheres (radius {RADIUS}, left to right)
     over a grey floor (0.5), max_depth {MAX_DEPTH}:
       {names}""", parts)
    return xml.replace("make_appearance_references.py", "make_material_references.py")


def scene_names():
    return [f"{g}-{l}" for g in GROUPS for l in LIGHTS]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes-only", action="store_true", help="write the scene files, render nothing")
    ap.add_argument("--only", action="append", help="this scene only (repeatable), e.g. conductor-env")
    ap.add_argument("--spp", type=int, default=REF_SPP, help="reference samples per pixel in all")
    ap.add_argument("--seeds", type=int, default=SEEDS)
    ap.add_argument("--preview", help="also write sRGB PNG previews into this folder")
    ap.add_argument("--check-stats", type=int, metavar="SPP",
                    help="do not render references: render each scene at SPP with Mitsuba (other "
                         "seeds) and apply the test's criteria against the stored reference")
    args = ap.parse_args()

    import mitsuba as mi
    mi.set_variant("scalar_rgb")

    names = args.only or scene_names()
    for n in names:
        if n not in scene_names():
            sys.exit(f"unknown scene {n}; known: {', '.join(scene_names())}")
    SCENES.mkdir(parents=True, exist_ok=True)
    REFS.mkdir(parents=True, exist_ok=True)
    write_aniso_sphere(SCENES / ANISO_MESH)
    if args.preview:
        Path(args.preview).mkdir(parents=True, exist_ok=True)

    meta_path = REFS / "mitsuba.json"
    meta = json.loads(meta_path.read_text()) if meta_path.exists() else {}
    meta.update({
        "renderer": "Mitsuba 3",
        "mitsuba_version": mi.__version__,
        "variant": "scalar_rgb",
        "integrator": f"path, max_depth {MAX_DEPTH} (wavepath depth {MAX_DEPTH - 1})",
        "sampler": "independent",
        "rfilter": "box",
        "variance": "<scene>.var.exr: variance of the mean, from the spread of K partial means "
                    "(seeds 1000 .. 1000 + K - 1)",
        "script": "scripts/make_material_references.py",
    })
    meta.setdefault("scenes", {})
    for n in names:
        group, light = n.rsplit("-", 1)
        xml_path = SCENES / f"{n}.xml"
        xml_path.write_text(scene(group, light))
        print(f"wrote {xml_path.relative_to(ROOT)}")
        if args.scenes_only:
            continue
        if args.check_stats:
            ref = np.array(mi.Bitmap(str(REFS / f"{n}.exr")))
            ref_var = np.array(mi.Bitmap(str(REFS / f"{n}.var.exr")))
            st = R.check_stats(mi, xml_path, ref, ref_var, meta["scenes"][n]["spp"], args.check_stats)
            print(f"  {n}: Mitsuba at {st['spp']} spp vs the reference: z-test pass "
                  f"{st['pass_fraction']:.4f} (|z| <= {st['z_crit']:.2f}, largest {st['max_z']:.2f}); "
                  f"relMSE {st['relmse']:.3e}, noise {st['noise']:.3e}, ratio {st['relmse_over_noise']:.3f}")
            continue
        spp = max(args.seeds, args.spp // args.seeds * args.seeds)
        t0 = time.time()
        mean, var, used = R.render_reference(mi, xml_path, spp, args.seeds)
        secs = time.time() - t0
        A.write_exr(REFS / f"{n}.exr", mean)
        A.write_exr(REFS / f"{n}.var.exr", var)
        own = float(np.mean(var / (mean.astype(np.float64) ** 2 + 1e-2)))
        meta["scenes"][n] = {"spp": used, "seeds": args.seeds, "width": int(mean.shape[1]),
                             "height": int(mean.shape[0]), "seconds": round(secs, 1),
                             "relmse_of_mean": float(f"{own:.3g}"),
                             "channel_means": [float(f"{c:.6g}") for c in mean.reshape(-1, 3).mean(0)]}
        print(f"  {n}: {used} spp in {args.seeds} seeds, {secs:.0f} s; own relMSE {own:.2e}; "
              f"means {mean.reshape(-1, 3).mean(0)}", flush=True)
        if args.preview:
            R.preview(mean, Path(args.preview) / f"{n}.png")
        # Written after every scene, so an interrupted run keeps what it made
        meta_path.write_text(json.dumps(meta, indent=2, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()

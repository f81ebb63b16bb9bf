#!/usr/bin/env python3
"""make_appearance_references.py — the Mitsuba 3 references of tests/test_appearance_reference.cpp.

Writes five small Mitsuba 3 XML scenes that wavepath's Mitsuba reader also reads, with the
meshes and textures they use (all procedural, written here), into tests/scenes/appearance/,
then renders each with Mitsuba 3 (scalar_rgb, path tracer) into
tests/references/appearance/<scene>.exr (linear RGB mean) and <scene>.var.exr (per-pixel
variance of that mean, from K independent seeds), and records Mitsuba's version and the
settings in tests/references/appearance/mitsuba.json.

Run on purpose only (the tests never make a missing reference):
    python3 -m venv /work/venv-mitsuba && /work/venv-mitsuba/bin/pip install mitsuba numpy
    /work/venv-mitsuba/bin/python scripts/make_appearance_references.py            # scenes + references
    /work/venv-mitsuba/bin/python scripts/make_appearance_references.py --scenes-only
    /work/venv-mitsuba/bin/python scripts/make_appearance_references.py --only env-spheres --preview /tmp/prev

Depth: Mitsuba's max_depth N counts path segments (1 = emitters seen directly); wavepath's
Mitsuba reader turns it into --depth N − 1 bounces (checked: a closed white box at max_depth
2, 3, 4 gives the same image means in both within 0.2 %). The scenes carry their max_depth,
so both renderers read the same depth from the same file.

Conventions checked empirically with Mitsuba 3.9.1 (see docs/testing.md):
  * rectangle uv = ((x + 1) / 2, (y + 1) / 2), and a bitmap's row 0 is at v = 0: seen from
    +z with +y up, a rectangle shows its image upside down;
  * OBJ vt is stored as (u, 1 − v): an OBJ quad whose vt grows with +y shows its image upright;
  * normalmap: green is n × dp/du (t of the shading frame), red dp/du, whatever the uv's
    handedness — on a rectangle and on such an OBJ quad green points to +y;
  * envmap: u = atan2(d.x, −d.z) / 2π, v = acos(d.y) / π in the map's frame
    (u = 0: −z, u = 0.25: +x, u = 0.5: +z, v = 0: +y), columns at texel centres
    (u = (x + 0.5) / W), rows on a pole-to-pole grid (v = y / (H − 1)), bilinear; to_world
    turns the map (world = to_world · local); scale multiplies.
"""
import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import appearance_assets as A  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "tests" / "scenes" / "appearance"
REFS = ROOT / "tests" / "references" / "appearance"

# Per scene: reference samples per pixel in all and the number of independent seeds they
# are split into (the variance of the mean comes from the spread of the K partial means).
SEEDS = 32


# --------------------------------------------------------------------------- XML helpers

def sensor(origin, target, fov, width, height, spp=64, up="0, 1, 0"):
    return f"""    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <transform name="to_world">
            <lookat origin="{origin}" target="{target}" up="{up}"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="{spp}"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="{width}"/>
            <integer name="height" value="{height}"/>
            <rfilter type="box"/>
        </film>
    </sensor>"""


def integrator(max_depth):
    return f"""    <integrator type="path">
        <integer name="max_depth" value="{max_depth}"/>
    </integrator>"""


def scene_xml(comment, parts):
    return ("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- " + comment.strip() +
            "\n     Written by scripts/make_appearance_references.py: edit the script, not this"
            " file. -->\n<scene version=\"3.0.0\">\n" + "\n".join(parts) + "\n</scene>\n")


def diffuse(reflectance_xml, twosided=True):
    inner = f'<bsdf type="diffuse">{reflectance_xml}</bsdf>'
    return f'<bsdf type="twosided">{inner}</bsdf>' if twosided else inner


def rgb(name, v):
    if isinstance(v, (int, float)):
        return f'<rgb name="{name}" value="{v}"/>'
    return f'<rgb name="{name}" value="{", ".join(A.fmt(c) for c in v)}"/>'


def bitmap(name, filename, filter_type=None, raw=None, to_uv=None):
    s = f'<texture type="bitmap" name="{name}"><string name="filename" value="{filename}"/>'
    if filter_type:
        s += f'<string name="filter_type" value="{filter_type}"/>'
    if raw is not None:
        s += f'<boolean name="raw" value="{"true" if raw else "false"}"/>'
    if to_uv:
        s += f'<transform name="to_uv">{to_uv}</transform>'
    return s + "</texture>"


def shape(kind, transform="", bsdf="", extra=""):
    t = f'\n        <transform name="to_world">{transform}</transform>' if transform else ""
    b = f"\n        {bsdf}" if bsdf else ""
    e = f"\n        {extra}" if extra else ""
    return f'    <shape type="{kind}">{t}{b}{e}\n    </shape>'


def area(radiance):
    return f'<emitter type="area">{rgb("radiance", radiance)}</emitter>'


def black():
    return '<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></bsdf>'


# --------------------------------------------------------------------------- the scenes

def quad_obj(path, comment):
    """The unit quad [−1, 1]² in z = 0, normal +z, vt = ((x + 1) / 2, (y + 1) / 2) (v up, as
    OBJ files store it: the image shows upright seen from +z), vn = +z."""
    pos = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    nrm = [(0, 0, 1)] * 4
    A.write_obj(path, pos, [(0, 1, 2), (0, 2, 3)], nrm, uv, comment)


def textured_quad(d):
    """(a) Image textures, uv orientation, sRGB decoding, bilinear and nearest lookups,
    to_uv, checkerboard."""
    # 8 x 8 albedo: a two-colour checker, a 2 x 2 red marker at the top-left corner and one
    # yellow texel at the top-right one; mid-tone values test the sRGB decoding.
    t = np.zeros((8, 8, 3), np.uint8)
    for y in range(8):
        for x in range(8):
            t[y, x] = (214, 130, 60) if (x + y) % 2 == 0 else (40, 150, 160)
    t[0:2, 0:2] = (220, 25, 25)
    t[0, 7] = (240, 230, 40)
    A.write_png(d / "textures" / "marker-checker.png", t)
    quad_obj(d / "meshes" / "quad.obj", "unit quad, vt v-up, vn +z")
    parts = [
        integrator(3),
        sensor("0, 0, 4", "0, 0, 0", 45, 64, 64),
        # The light: a 6 x 6 square behind the camera, facing −z.
        shape("rectangle", '<scale x="3" y="3"/><rotate y="1" angle="180"/><translate z="5"/>',
              black(), area(3.0)),
        # Backdrop: checkerboard, 3 periods across (to_uv scale 3).
        shape("rectangle", '<scale x="2.2" y="2.2"/><translate z="-0.5"/>',
              diffuse('<texture type="checkerboard" name="reflectance">'
                      + rgb("color0", (0.8, 0.8, 0.8)) + rgb("color1", (0.1, 0.25, 0.5))
                      + '<transform name="to_uv"><scale x="3" y="3"/></transform></texture>')),
        # Left: the OBJ quad, bilinear (Mitsuba's default), sRGB.
        shape("obj", '<scale value="0.55"/><translate x="-0.7" y="0.1"/>',
              diffuse(bitmap("reflectance", "textures/marker-checker.png")),
              '<string name="filename" value="meshes/quad.obj"/>'),
        # Right: Mitsuba's rectangle (its own uv), nearest lookups, to_uv: u' = 2u + 0.5.
        shape("rectangle", '<scale value="0.55"/><translate x="0.7" y="-0.1"/>',
              diffuse(bitmap("reflectance", "textures/marker-checker.png", "nearest",
                             to_uv='<scale x="2" y="1"/><translate x="0.5"/>'))),
    ]
    return scene_xml("""(a) textured quads: an 8x8 sRGB PNG (checker + red marker top-left + yellow texel
     top-right) on an OBJ quad (vt, bilinear) and on a rectangle (nearest, to_uv), a checkerboard
     backdrop; lit by a square area light behind the camera.""", parts)


def smooth_spheres(d):
    """(b) Per-vertex shading normals on coarse spheres: a mirror (OBJ vn) and a glass (PLY
    normals) sphere in a box."""
    pos, nrm, tris = A.uv_sphere(10, 20)
    A.check_outward(pos, tris)
    A.write_obj(d / "meshes" / "sphere-10x20.obj", pos, tris, nrm, None,
                "UV sphere, 10 stacks x 20 slices, radius 1, exact vertex normals")
    pos, nrm, tris = A.uv_sphere(12, 24)
    A.check_outward(pos, tris)
    A.write_ply(d / "meshes" / "sphere-12x24.ply", pos, tris, nrm)
    white, red, green = (0.725, 0.71, 0.68), (0.63, 0.065, 0.05), (0.14, 0.45, 0.091)
    parts = [
        integrator(8),
        # Close up: the spheres fill most of the frame, the box shows in them.
        sensor("0, -0.3, 2.7", "0, -0.5, 0", 44, 96, 48),
        shape("rectangle", '<scale x="0.6" y="0.6"/><rotate x="1" angle="90"/><translate y="0.99"/>',
              black(), area((2.8, 2.4, 1.8))),
        shape("rectangle", '<rotate x="1" angle="-90"/><translate y="-1"/>', diffuse(rgb("reflectance", white))),
        shape("rectangle", '<rotate x="1" angle="90"/><translate y="1"/>', diffuse(rgb("reflectance", white))),
        shape("rectangle", '<translate z="-1"/>', diffuse(rgb("reflectance", white))),
        shape("rectangle", '<rotate y="1" angle="90"/><translate x="-1"/>', diffuse(rgb("reflectance", red))),
        shape("rectangle", '<rotate y="1" angle="-90"/><translate x="1"/>', diffuse(rgb("reflectance", green))),
        shape("obj", '<scale value="0.47"/><translate x="-0.45" y="-0.52" z="-0.3"/>',
              '<bsdf type="conductor"><string name="material" value="none"/></bsdf>',
              '<string name="filename" value="meshes/sphere-10x20.obj"/>'),
        shape("ply", '<scale value="0.47"/><translate x="0.47" y="-0.52" z="0.25"/>',
              '<bsdf type="dielectric"><float name="int_ior" value="1.5"/>'
              '<float name="ext_ior" value="1"/></bsdf>',
              '<string name="filename" value="meshes/sphere-12x24.ply"/>'),
    ]
    return scene_xml("""(b) smooth shading normals: a coarse mirror sphere (OBJ with vn, 10x20) and a coarse
     glass sphere (binary PLY with normals, 12x24) in a box with a ceiling light.""", parts)


def normal_map(d):
    """(c) Tangent-space normal map on an OBJ quad (vt v-up) and on a rectangle."""
    n = 24
    yy, xx = np.mgrid[0:n, 0:n] + 0.5
    h = np.zeros((n, n))
    # Asymmetric bumps (row 0 = image top): a big one upper-left, a small one lower-right,
    # a dent lower-left, a ridge along the right edge's upper half.
    for cx, cy, r, a in [(6, 6, 3.5, 1.0), (17, 17, 2.5, 0.7), (6, 18, 2.5, -0.8)]:
        h += a * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * r * r))
    h += 0.9 * np.exp(-((xx - 19.5) ** 2) / (2 * 1.5 ** 2)) * (yy < 11)
    nm = A.normal_map_from_height(h, 3.0)
    A.write_png(d / "textures" / "bumps-normal.png", A.to_u8(nm))
    quad_obj(d / "meshes" / "quad.obj", "unit quad, vt v-up, vn +z")
    nmap = ('<bsdf type="normalmap">'
            + bitmap("normalmap", "textures/bumps-normal.png", raw=True)
            + '<bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf></bsdf>')
    nmap = f'<bsdf type="twosided">{nmap}</bsdf>'
    parts = [
        integrator(3),
        sensor("0, 0, 4", "0, 0, 0", 50, 96, 48),
        # Light: a 1 x 1 square up-left, facing the origin (~40 degrees off the quads'
        # normal, so that tilts toward and away from it differ clearly).
        shape("rectangle", '<scale value="0.5"/><lookat origin="-2.2, 2.2, 3.6" target="0, 0, 0" up="0, 1, 0"/>',
              black(), area(60.0)),
        shape("obj", '<scale value="0.8"/><translate x="-0.95"/>', nmap,
              '<string name="filename" value="meshes/quad.obj"/>'),
        shape("rectangle", '<scale value="0.8"/><translate x="0.95"/>', nmap),
    ]
    return scene_xml("""(c) a tangent-space normal map (24x24, raw, bilinear; bumps, a dent and a ridge) on an
     OBJ quad (left, vt v-up) and on a rectangle (right), lit by a small square light up-left.""", parts)


ENV_ROTATION = [((0, 1, 0), -60.0), ((1, 0, 0), 10.0)]  # applied in this order
ENV_SCALE = 1.5


def env_spheres(d):
    """(d) Environment light: a 2:1 EXR sky with a sun, rotated and scaled; a diffuse and a
    glossy sphere."""
    r = np.eye(3)
    for axis, ang in ENV_ROTATION:
        r = A.rotation_matrix(axis, ang) @ r
    to_local = r.T
    sun_world = np.array([-0.55, 0.6, 0.55])
    blob_world = np.array([0.3, 0.15, -1.0])
    sky = A.sky_map(128, 64, to_local @ sun_world, 4.0, (40.0, 35.0, 27.0),
                    zenith=(0.12, 0.22, 0.55), horizon=(0.45, 0.47, 0.52),
                    ground=(0.16, 0.11, 0.07), horizon_soft_deg=6.0,
                    blobs=[(to_local @ blob_world, 8.0, (0.6, 0.05, 0.02))])
    A.write_exr(d / "textures" / "sky-128x64.exr", sky)
    pos, nrm, tris = A.uv_sphere(24, 48)
    A.check_outward(pos, tris)
    A.write_ply(d / "meshes" / "sphere-24x48.ply", pos, tris, nrm)
    rot = "".join(f'<rotate x="{a[0]}" y="{a[1]}" z="{a[2]}" angle="{ang}"/>' for a, ang in ENV_ROTATION)
    parts = [
        integrator(4),
        sensor("0, 0.3, 4", "0, 0, 0", 50, 96, 48),
        f"""    <emitter type="envmap">
        <string name="filename" value="textures/sky-128x64.exr"/>
        <float name="scale" value="{ENV_SCALE}"/>
        <transform name="to_world">{rot}</transform>
    </emitter>""",
        shape("ply", '<scale value="0.8"/><translate x="-0.95"/>',
              diffuse(rgb("reflectance", (0.8, 0.8, 0.8))),
              '<string name="filename" value="meshes/sphere-24x48.ply"/>'),
        shape("ply", '<scale value="0.8"/><translate x="0.95"/>',
              '<bsdf type="twosided"><bsdf type="roughconductor"><string name="material" value="none"/>'
              '<string name="distribution" value="ggx"/><float name="alpha" value="0.15"/></bsdf></bsdf>',
              '<string name="filename" value="meshes/sphere-24x48.ply"/>'),
    ]
    return scene_xml(f"""(d) environment light: a 128x64 EXR sky (gradient, soft horizon, a sun of sigma 4 degrees
     up-left-front, a red blob up-right-behind the spheres), scale {ENV_SCALE}, turned by to_world;
     a white diffuse sphere (left) and a GGX roughconductor sphere alpha 0.15, F = 1 (right),
     both smooth (PLY with normals, 24x48).""", parts)


def alpha_mask(d):
    """(e) Alpha cut-out: a mask BSDF with a 0/1 opacity bitmap over an emitting quad."""
    n = 16
    m = np.ones((n, n), np.uint8) * 255
    yy, xx = np.mgrid[0:n, 0:n] + 0.5
    m[(xx - 4.5) ** 2 + (yy - 4.5) ** 2 < 3.2 ** 2] = 0   # round hole, upper left
    m[2:10, 12:14] = 0                                     # vertical slot, upper right
    m[12:14, 2:4] = 0                                      # small squares, bottom row
    m[12:14, 7:9] = 0
    m[11:15, 11:15] = 0                                    # bigger square, bottom right
    rgba = np.repeat(m[:, :, None], 4, axis=2)             # R = G = B = A: 0 or 255
    A.write_png(d / "textures" / "holes-mask.png", rgba)
    masked = ('<bsdf type="mask">'
              + bitmap("opacity", "textures/holes-mask.png", "nearest", raw=True)
              + diffuse(rgb("reflectance", (0.7, 0.5, 0.3))) + "</bsdf>")
    parts = [
        integrator(3),
        sensor("0, 0.6, 4", "0, -0.1, 0", 40, 64, 64),
        '    <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>',
        shape("rectangle", '<scale x="1.2" y="0.9"/><translate y="0.1" z="-1"/>',
              black(), area((4.0, 3.5, 2.5))),
        shape("rectangle", '<scale x="1.0" y="0.8"/><translate y="0.1"/>', masked),
        shape("rectangle", '<scale value="2"/><rotate x="1" angle="-90"/><translate y="-0.8"/>',
              diffuse(rgb("reflectance", 0.6))),
    ]
    return scene_xml("""(e) alpha cut-out: a quad with a mask BSDF (16x16 0/1 opacity PNG, nearest: holes of
     several shapes) in front of an emitting quad, over a floor that the light reaches through the
     holes; a dim constant background.""", parts)


SCENE_LIST = {
    # name: (writer, reference spp in all)
    "textured-quad": (textured_quad, 8192),
    "smooth-spheres": (smooth_spheres, 16384),
    "normal-map": (normal_map, 8192),
    "env-spheres": (env_spheres, 8192),
    "alpha-mask": (alpha_mask, 8192),
}


# --------------------------------------------------------------------------- rendering

def render_reference(mi, xml_path, spp_total, seeds, seed0=1000):
    scene = mi.load_file(str(xml_path))
    per = spp_total // seeds
    acc = None
    acc2 = None
    for k in range(seeds):
        img = np.array(mi.render(scene, spp=per, seed=seed0 + k), dtype=np.float64)
        acc = img if acc is None else acc + img
        acc2 = img * img if acc2 is None else acc2 + img * img
    mean = acc / seeds
    # unbiased sample variance of the K partial means, divided by K: variance of the mean
    var = np.maximum(acc2 / seeds - mean * mean, 0.0) * seeds / (seeds - 1) / seeds
    return mean.astype(np.float32), var.astype(np.float32), per * seeds


def check_stats(mi, xml_path, ref, ref_var, ref_spp, spp, parts=32, min_pass=None, allowance=0.0):
    """Stand Mitsuba in for wavepath: render `spp` samples with other seeds and apply the
    test's formulas (tests/test_appearance_reference.cpp), to see what noise alone gives."""
    from statistics import NormalDist
    mean, var, used = render_reference(mi, xml_path, spp, parts, seed0=7000)
    ref = ref.astype(np.float64)
    ref_var = ref_var.astype(np.float64)
    var_a = np.maximum(ref_var * ref_spp / used, var)
    n = ref.shape[0] * ref.shape[1]
    alpha_ch = -math.expm1(math.log1p(-0.01) / (3.0 * n))
    z_crit = NormalDist().inv_cdf(1.0 - alpha_ch / 2.0)
    floor = (1e-5 * np.maximum(np.abs(mean), np.abs(ref))) ** 2 + 1e-24
    z = np.abs(mean - ref) / np.sqrt(var_a + ref_var + floor)
    passed = float(np.mean(z.max(axis=2) <= z_crit))
    eps = 1e-2
    relmse = float(np.mean((mean - ref) ** 2 / (ref * ref + eps)))
    noise = float(np.mean(var_a / (ref * ref + eps)) + np.mean(ref_var / (ref * ref + eps)))
    return {"spp": used, "pass_fraction": passed, "z_crit": z_crit, "max_z": float(z.max()),
            "relmse": relmse, "noise": noise, "relmse_over_noise": relmse / noise}


def preview(img, path, zoom=4):
    """sRGB PNG of a linear image, each pixel zoom x zoom (for looking at, not for tests)."""
    big = np.repeat(np.repeat(img, zoom, axis=0), zoom, axis=1)
    A.write_png(path, A.to_u8(A.srgb_encode(big)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes-only", action="store_true", help="write the scene files, render nothing")
    ap.add_argument("--only", action="append", help="this scene only (repeatable)")
    ap.add_argument("--spp-scale", type=float, default=1.0, help="multiply every reference spp (tests of this script)")
    ap.add_argument("--seeds", type=int, default=SEEDS)
    ap.add_argument("--preview", help="also write sRGB PNG previews into this folder")
    ap.add_argument("--check-stats", type=int, metavar="SPP",
                    help="do not render references: render each scene at SPP with Mitsuba (other "
                         "seeds) and apply the test's criteria against the stored reference")
    args = ap.parse_args()

    import mitsuba as mi
    mi.set_variant("scalar_rgb")

    names = args.only or list(SCENE_LIST)
    for n in names:
        if n not in SCENE_LIST:
            sys.exit(f"unknown scene {n}; known: {', '.join(SCENE_LIST)}")
    for sub in ("textures", "meshes"):
        (SCENES / sub).mkdir(parents=True, exist_ok=True)
    REFS.mkdir(parents=True, exist_ok=True)
    if args.preview:
        Path(args.preview).mkdir(parents=True, exist_ok=True)

    meta_path = REFS / "mitsuba.json"
    meta = json.loads(meta_path.read_text()) if meta_path.exists() else {}
    meta.update({
        "renderer": "Mitsuba 3",
        "mitsuba_version": mi.__version__,
        "variant": "scalar_rgb",
        "integrator": "path (max_depth from each scene file; wavepath depth = max_depth - 1)",
        "sampler": "independent",
        "rfilter": "box",
        "variance": "<scene>.var.exr: variance of the mean, from the spread of K partial means "
                    "(seeds 1000 .. 1000 + K - 1)",
        "script": "scripts/make_appearance_references.py",
    })
    meta.setdefault("scenes", {})
    for n in names:
        writer, spp = SCENE_LIST[n]
        xml = writer(SCENES)
        xml_path = SCENES / f"{n}.xml"
        xml_path.write_text(xml)
        print(f"wrote {xml_path.relative_to(ROOT)}")
        if args.scenes_only:
            continue
        if args.check_stats:
            ref = np.array(mi.Bitmap(str(REFS / f"{n}.exr")))
            ref_var = np.array(mi.Bitmap(str(REFS / f"{n}.var.exr")))
            st = check_stats(mi, xml_path, ref, ref_var, meta["scenes"][n]["spp"], args.check_stats)
            print(f"  {n}: Mitsuba at {st['spp']} spp vs the reference: z-test pass "
                  f"{st['pass_fraction']:.4f} (|z| <= {st['z_crit']:.2f}, largest {st['max_z']:.2f}); "
                  f"relMSE {st['relmse']:.3e}, noise {st['noise']:.3e}, ratio {st['relmse_over_noise']:.3f}")
            continue
        spp = max(args.seeds, int(spp * args.spp_scale) // args.seeds * args.seeds)
        t0 = time.time()
        mean, var, used = render_reference(mi, xml_path, spp, args.seeds)
        secs = time.time() - t0
        A.write_exr(REFS / f"{n}.exr", mean)
        A.write_exr(REFS / f"{n}.var.exr", var)
        eps = 1e-2
        own = float(np.mean(var / (mean.astype(np.float64) ** 2 + eps)))
        meta["scenes"][n] = {"spp": used, "seeds": args.seeds, "width": int(mean.shape[1]),
                             "height": int(mean.shape[0]), "seconds": round(secs, 1),
                             "relmse_of_mean": float(f"{own:.3g}"),
                             "channel_means": [float(f"{c:.6g}") for c in mean.reshape(-1, 3).mean(0)]}
        print(f"  {n}: {used} spp in {args.seeds} seeds, {secs:.0f} s; own relMSE {own:.2e}; "
              f"means {mean.reshape(-1, 3).mean(0)}")
        if args.preview:
            preview(mean, Path(args.preview) / f"{n}.png")
    if not args.scenes_only and not args.check_stats:
        meta_path.write_text(json.dumps(meta, indent=2, sort_keys=True) + "\n")
        print(f"wrote {meta_path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""make_showcase.py — the textured, environment-lit showcase scene, made procedurally.

Writes scenes/showcase-env.xml (Mitsuba 3 XML in the subset wavepath's reader takes, so
both renderers read the same file) and its files under scenes/showcase-env/: a procedural
sky (gradient + sun disc, 2:1 EXR), a brick albedo with its tangent-space normal map, a
lattice fence's opacity, and a smooth UV-sphere mesh (PLY with normals). No copied assets.
Then, unless --no-render, renders it with Mitsuba 3 (scalar_rgb) at 256x192 into
docs/showcase-mitsuba.png for comparison with wavepath's image.

    /work/venv-mitsuba/bin/python scripts/make_showcase.py [--spp 512] [--no-render]
    build/release/wavepath render scenes/showcase-env.xml -o showcase.png   # wavepath's

What it shows: a checkerboard floor (Mitsuba checkerboard, to_uv), a brick wall (sRGB
bitmap albedo + raw normal map, OBJ quad with vt), a lattice fence cut out by a mask
(0/1 opacity, nearest), smooth spheres (mirror, glass, gold-like GGX roughconductor, and a
diffuse one), all lit by the sky (envmap with scale and to_world) and nothing else.
"""
import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import appearance_assets as A  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "scenes" / "showcase-env"
XML = ROOT / "scenes" / "showcase-env.xml"
PNG = ROOT / "docs" / "showcase-mitsuba.png"


def bricks(size=256, rows=8, cols=4, mortar=3, seed=13):
    """Brick albedo (sRGB-encoded uint8) and height field (1 on bricks, 0 in the mortar,
    bevelled edges); a per-brick tint and faint noise."""
    rng = np.random.default_rng(seed)
    row_h = size // rows
    brick_w = size // cols
    yy, xx = np.mgrid[0:size, 0:size]
    row = yy // row_h
    xs = (xx + (row % 2) * (brick_w // 2)) % size
    col = xs // brick_w
    # distance to the nearest mortar line, in texels
    dy = np.minimum(yy % row_h, row_h - 1 - yy % row_h)
    dx = np.minimum(xs % brick_w, brick_w - 1 - xs % brick_w)
    dist = np.minimum(dx, dy).astype(np.float64)
    height = np.clip((dist - mortar + 1) / 3.0, 0.0, 1.0)
    height = height * height * (3 - 2 * height)  # smoothstep bevel
    tints = rng.uniform(0.75, 1.15, size=(rows, cols + 1))
    base = np.array([0.42, 0.14, 0.08])
    tint = tints[row, col][..., None]
    noise = rng.normal(0.0, 0.025, size=(size, size, 1))
    albedo_brick = np.clip(base * tint * (1.0 + noise), 0, 1)
    albedo_mortar = np.array([0.55, 0.53, 0.5]) * (1.0 + 0.5 * noise)
    m = height[..., None]
    albedo = m * albedo_brick + (1 - m) * albedo_mortar
    height = height + 0.02 * rng.normal(size=(size, size))  # a little surface roughness
    return A.to_u8(A.srgb_encode(albedo)), height


def lattice(size=128, slat=10, period=32):
    """Opacity of a diagonal lattice fence with a frame: 255 on wood, 0 in the gaps."""
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    a = (xx + yy) % period < slat
    b = (xx - yy) % period < slat
    frame = (xx < 8) | (xx > size - 8) | (yy < 8) | (yy > size - 8)
    m = (a | b | frame).astype(np.uint8) * 255
    return np.repeat(m[:, :, None], 4, axis=2)


def write_assets():
    (OUT).mkdir(parents=True, exist_ok=True)
    albedo, height = bricks()
    A.write_png(OUT / "brick-albedo.png", albedo)
    A.write_png(OUT / "brick-normal.png", A.to_u8(A.normal_map_from_height(height, 2.5)))
    A.write_png(OUT / "fence-opacity.png", lattice())
    sun = np.array([-0.45, 0.55, 0.7])  # up, left, behind the camera: light on the front
    sky = A.sky_map(256, 128, sun, 0.0, (0, 0, 0), zenith=(0.06, 0.15, 0.50),
                    horizon=(0.38, 0.48, 0.68), ground=(0.20, 0.17, 0.13),
                    horizon_soft_deg=3.0)
    # The sun: a disc of 2 degrees radius (a few texels), radiance 600, plus a soft glow.
    u = (np.arange(256) + 0.5) / 256
    v = np.arange(128) / 127
    phi, theta = 2 * np.pi * u[None, :], np.pi * v[:, None]
    d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta) * np.ones_like(phi),
                  -np.cos(phi) * np.sin(theta)], axis=-1)
    ang = np.degrees(np.arccos(np.clip(d @ (sun / np.linalg.norm(sun)), -1, 1)))
    sky += ((ang < 2.0) * 600.0)[..., None] * np.array([1.0, 0.92, 0.8], dtype=np.float32)
    sky += (4.0 * np.exp(-ang / 6.0))[..., None] * np.array([1.0, 0.85, 0.6], dtype=np.float32)
    A.write_exr(OUT / "sky.exr", sky)
    pos, nrm, tris = A.uv_sphere(32, 64)
    A.check_outward(pos, tris)
    A.write_ply(OUT / "sphere.ply", pos, tris, nrm)
    A.write_obj(OUT / "quad.obj", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)],
                [(0, 1, 2), (0, 2, 3)], [(0, 0, 1)] * 4, [(0, 0), (1, 0), (1, 1), (0, 1)],
                "unit quad, vt v-up, vn +z")


def scene_xml(spp):
    d = "showcase-env"

    def sphere(x, z, r, bsdf):
        return (f'    <shape type="ply"><string name="filename" value="{d}/sphere.ply"/>'
                f'<transform name="to_world"><scale value="{r}"/><translate x="{x}" y="{r}" z="{z}"/>'
                f'</transform>{bsdf}</shape>')

    return f"""<?xml version="1.0" encoding="utf-8"?>
<!-- wavepath's textured, environment-lit showcase: written by scripts/make_showcase.py (edit
     the script, not this file). Mitsuba 3 reads it as it is; docs/showcase-mitsuba.png is
     Mitsuba's image of it. Everything here is procedural. -->
<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="8"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="48"/>
        <transform name="to_world"><lookat origin="0.3, 1.1, 5.2" target="0, 0.75, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
        <film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="192"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="envmap">
        <string name="filename" value="{d}/sky.exr"/>
        <float name="scale" value="1.0"/>
        <transform name="to_world"><rotate y="1" angle="-25"/></transform>
    </emitter>
    <!-- floor: a checkerboard, 1 unit per square -->
    <shape type="rectangle">
        <transform name="to_world"><scale value="12"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="twosided"><bsdf type="diffuse">
            <texture type="checkerboard" name="reflectance">
                <rgb name="color0" value="0.72, 0.72, 0.68"/><rgb name="color1" value="0.12, 0.13, 0.15"/>
                <transform name="to_uv"><scale x="12" y="12"/></transform>
            </texture>
        </bsdf></bsdf>
    </shape>
    <!-- a low brick wall: sRGB albedo and a raw normal map (to_uv 3 x 1) -->
    <shape type="obj">
        <string name="filename" value="{d}/quad.obj"/>
        <transform name="to_world"><scale x="2.4" y="0.7"/><translate x="-0.3" y="0.7" z="-1.5"/></transform>
        <bsdf type="twosided"><bsdf type="normalmap">
            <texture type="bitmap" name="normalmap"><string name="filename" value="{d}/brick-normal.png"/>
                <boolean name="raw" value="true"/><transform name="to_uv"><scale x="3" y="1"/></transform></texture>
            <bsdf type="diffuse">
                <texture type="bitmap" name="reflectance"><string name="filename" value="{d}/brick-albedo.png"/>
                    <transform name="to_uv"><scale x="3" y="1"/></transform></texture>
            </bsdf>
        </bsdf></bsdf>
    </shape>
    <!-- lattice fence on the right: cut out by a 0/1 mask -->
    <shape type="rectangle">
        <transform name="to_world"><scale x="0.9" y="0.6"/><rotate y="1" angle="-60"/><translate x="1.95" y="0.6" z="0.1"/></transform>
        <bsdf type="mask">
            <texture type="bitmap" name="opacity"><string name="filename" value="{d}/fence-opacity.png"/>
                <string name="filter_type" value="nearest"/><boolean name="raw" value="true"/></texture>
            <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.45, 0.3, 0.17"/></bsdf></bsdf>
        </bsdf>
    </shape>
    <!-- smooth spheres: mirror, glass, gold-like GGX, white diffuse -->
{sphere(-1.55, -0.3, 0.5, '<bsdf type="twosided"><bsdf type="conductor"><string name="material" value="none"/></bsdf></bsdf>')}
{sphere(-0.45, 0.45, 0.5, '<bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>')}
{sphere(0.7, -0.1, 0.55, '<bsdf type="twosided"><bsdf type="roughconductor"><string name="material" value="Au"/><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf></bsdf>')}
{sphere(1.05, 1.05, 0.3, '<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></bsdf>')}
</scene>
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=2048, help="Mitsuba's samples per pixel (default 2048)")
    ap.add_argument("--no-render", action="store_true", help="write the scene only")
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    write_assets()
    XML.write_text(scene_xml(64))
    total = sum(f.stat().st_size for f in OUT.iterdir()) + XML.stat().st_size
    print(f"wrote {XML.relative_to(ROOT)} and {OUT.relative_to(ROOT)}/ ({total / 1024:.0f} KiB)")
    if args.no_render:
        return
    t0 = time.time()
    img = np.array(mi.render(mi.load_file(str(XML)), spp=args.spp, seed=1))
    A.write_png(PNG, A.to_u8(A.srgb_encode(img)))
    print(f"wrote {PNG.relative_to(ROOT)} (Mitsuba {mi.__version__} scalar_rgb, {args.spp} spp, "
          f"{time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main()

"""appearance_assets.py — small writers shared by make_appearance_references.py and
make_showcase.py: PNG (8-bit, no colour chunks: readers take it as sRGB unless told raw),
EXR (through Mitsuba's Bitmap), OBJ and binary PLY meshes with per-vertex normals, UV spheres,
normal maps from height fields, and a procedural sky.

Only numpy and the standard library here; EXR writing imports mitsuba lazily (the caller has
set a variant). Every writer is deterministic: the same call writes the same bytes.
"""
import math
import struct
import zlib

import numpy as np


def write_png(path, arr):
    """8-bit PNG of an (h, w), (h, w, 3) or (h, w, 4) uint8 array; row 0 is the top row."""
    arr = np.ascontiguousarray(arr, dtype=np.uint8)
    h, w = arr.shape[:2]
    c = 1 if arr.ndim == 2 else arr.shape[2]
    ctype = {1: 0, 3: 2, 4: 6}[c]
    raw = b"".join(b"\x00" + arr[y].tobytes() for y in range(h))

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, ctype, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def write_exr(path, rgb):
    """Linear float32 RGB EXR of an (h, w, 3) array, row 0 the top row (Mitsuba's writer)."""
    import mitsuba as mi
    mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32)).write(str(path))


def srgb_encode(x):
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def to_u8(x):
    return np.clip(np.round(np.asarray(x) * 255.0), 0, 255).astype(np.uint8)


def fmt(v):
    return f"{v:.7g}"


def write_obj(path, positions, triangles, normals=None, uvs_vup=None, comment=""):
    """OBJ with v, optional vn and vt (given v-up, as OBJ stores them), f with shared indices."""
    lines = []
    if comment:
        lines += ["# " + c for c in comment.splitlines()]
    for p in positions:
        lines.append("v " + " ".join(fmt(c) for c in p))
    if uvs_vup is not None:
        for t in uvs_vup:
            lines.append("vt " + " ".join(fmt(c) for c in t))
    if normals is not None:
        for n in normals:
            lines.append("vn " + " ".join(fmt(c) for c in n))
    for tri in triangles:
        idx = [i + 1 for i in tri]
        if uvs_vup is not None and normals is not None:
            lines.append("f " + " ".join(f"{i}/{i}/{i}" for i in idx))
        elif normals is not None:
            lines.append("f " + " ".join(f"{i}//{i}" for i in idx))
        elif uvs_vup is not None:
            lines.append("f " + " ".join(f"{i}/{i}" for i in idx))
        else:
            lines.append("f " + " ".join(str(i) for i in idx))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_ply(path, positions, triangles, normals=None, uvs=None):
    """Binary little-endian PLY: float x y z [nx ny nz] [u v], faces as uchar/int lists.
    uvs are written as stored in the file (PLY, like OBJ, is read v-up by Mitsuba)."""
    positions = np.asarray(positions, dtype=np.float32)
    cols = [positions]
    props = ["x", "y", "z"]
    if normals is not None:
        cols.append(np.asarray(normals, dtype=np.float32))
        props += ["nx", "ny", "nz"]
    if uvs is not None:
        cols.append(np.asarray(uvs, dtype=np.float32))
        props += ["u", "v"]
    verts = np.ascontiguousarray(np.concatenate(cols, axis=1), dtype="<f4")
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(positions)}"]
    header += [f"property float {p}" for p in props]
    header += [f"element face {len(triangles)}", "property list uchar int vertex_indices",
               "end_header"]
    faces = b"".join(struct.pack("<Biii", 3, *map(int, t)) for t in triangles)
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(verts.tobytes())
        f.write(faces)


def uv_sphere(stacks, slices, radius=1.0):
    """A UV sphere around the origin, +y the pole axis, counter-clockwise seen from outside.
    Vertices on rings (the poles single vertices); normals = exact unit normals of the
    sphere (what a smooth-shaded export writes). Returns positions, normals, triangles."""
    pos, nrm = [], []
    pos.append((0.0, radius, 0.0))
    nrm.append((0.0, 1.0, 0.0))
    for i in range(1, stacks):
        theta = math.pi * i / stacks
        for j in range(slices):
            phi = 2.0 * math.pi * j / slices
            n = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
            nrm.append(n)
            pos.append(tuple(radius * c for c in n))
    pos.append((0.0, -radius, 0.0))
    nrm.append((0.0, -1.0, 0.0))
    south = len(pos) - 1

    def ring(i, j):
        return 1 + (i - 1) * slices + (j % slices)

    tris = []
    for j in range(slices):
        tris.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, stacks - 1):
        for j in range(slices):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            tris.append((a, c, d))
            tris.append((a, d, b))
    for j in range(slices):
        tris.append((ring(stacks - 1, j), south, ring(stacks - 1, j + 1)))
    return np.array(pos), np.array(nrm), tris


def check_outward(positions, triangles):
    """Every triangle's geometric normal points away from the origin (sphere sanity check)."""
    p = np.asarray(positions)
    for t in triangles:
        a, b, c = p[list(t)]
        n = np.cross(b - a, c - a)
        assert np.dot(n, (a + b + c) / 3.0) > 0.0, "inward triangle"


def normal_map_from_height(h, strength):
    """Tangent-space normal map (RGB in [0, 1]) of a height field h[row, col], row 0 at the
    top of the image. Tangent-space x is +u (image right), y is image-up (−row: OpenGL's
    green-up convention; Mitsuba maps green to n × dp/du, see the references' notes)."""
    gy, gx = np.gradient(h)  # per texel: gx along +col, gy along +row (down)
    n = np.stack([-strength * gx, strength * gy, np.ones_like(h)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return 0.5 * n + 0.5


def sky_map(width, height, sun_dir, sun_sigma_deg, sun_peak, zenith, horizon, ground,
            horizon_soft_deg=8.0, blobs=()):
    """Equirectangular sky (height x width x 3, linear) in Mitsuba 3's envmap convention:
    pixel (x, y) is the direction at u = (x + 0.5) / width, v = y / (height − 1)
    (Mitsuba's envmap puts rows on a pole-to-pole grid and columns at texel centres),
    d = (sin φ sin θ, cos θ, −cos φ sin θ) with φ = 2π u, θ = π v: u = 0 looks down −z,
    u = 0.25 +x, v = 0 is +y. Gradient sky, soft horizon, a Gaussian sun of sun_sigma_deg
    around sun_dir (local frame) with peak radiance sun_peak (rgb; none if sun_sigma_deg is 0), and Gaussian blobs
    (dir, sigma_deg, rgb) added on top."""
    u = (np.arange(width) + 0.5) / width
    v = np.arange(height) / (height - 1)
    phi = 2.0 * np.pi * u[None, :]
    theta = np.pi * v[:, None]
    d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta) * np.ones_like(phi),
                  -np.cos(phi) * np.sin(theta)], axis=-1)
    elev = np.degrees(np.arcsin(np.clip(d[..., 1], -1, 1)))
    t_sky = np.clip(elev / 90.0, 0.0, 1.0)[..., None]
    sky = (1 - t_sky) * np.asarray(horizon) + t_sky * np.asarray(zenith)
    w = (0.5 + 0.5 * np.tanh(elev / horizon_soft_deg))[..., None]
    img = w * sky + (1 - w) * np.asarray(ground)

    def gauss(direction, sigma_deg):
        dd = np.asarray(direction, dtype=np.float64)
        dd /= np.linalg.norm(dd)
        ang = np.arccos(np.clip(d @ dd, -1, 1))
        return np.exp(-0.5 * (ang / np.radians(sigma_deg)) ** 2)[..., None]

    if sun_sigma_deg > 0:
        img = img + gauss(sun_dir, sun_sigma_deg) * np.asarray(sun_peak)
    for bdir, bsig, brgb in blobs:
        img = img + gauss(bdir, bsig) * np.asarray(brgb)
    return img.astype(np.float32)


def dir_to_mitsuba_uv(d):
    """Mitsuba 3 envmap: local direction -> (u, v) (u in [0, 1), v in [0, 1])."""
    x, y, z = d / np.linalg.norm(d)
    u = math.atan2(x, -z) / (2 * math.pi)
    return (u + 1.0) % 1.0, math.acos(max(-1.0, min(1.0, y))) / math.pi


def rotation_matrix(axis, angle_deg):
    """Rotation about `axis` by angle_deg (right hand), as Mitsuba's <rotate>."""
    a = np.asarray(axis, dtype=np.float64)
    a /= np.linalg.norm(a)
    t = math.radians(angle_deg)
    c, s = math.cos(t), math.sin(t)
    x, y, z = a
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])

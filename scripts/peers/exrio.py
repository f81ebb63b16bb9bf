"""exrio.py — read the RGB channels of an OpenEXR file into a float64 numpy array (H, W, 3).

Three readers, first that works:
  1. OpenImageIO's Python module, when importable;
  2. a small reader here for scanline files without compression or with RLE, ZIPS or ZIP
     (what `wavepath render -o x.exr` writes: float, ZIP; Blender writes these too);
  3. OpenEXR's C API (ImfOpenInputFile ...) through ctypes, for everything else (PIZ,
     B44, DWA, tiles: the shipped references are half PIZ). It reads through ImfRgba, that
     is as half floats: exact for half files, within 2^-11 relative otherwise.
"""
import ctypes
import glob
import os
import struct
import zlib

import numpy as np

__all__ = ["read_rgb"]

_NONE, _RLE, _ZIPS, _ZIP = 0, 1, 2, 3
_LINES_PER_BLOCK = {_NONE: 1, _RLE: 1, _ZIPS: 1, _ZIP: 16}
_DTYPE = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


class Unsupported(Exception):
    pass


def _parse_header(data):
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file (bad magic number)")
    flags = struct.unpack_from("<I", data, 4)[0]
    if flags & 0x1A00:  # tiled (0x200), deep (0x800), multi-part (0x1000)
        raise Unsupported("tiled, deep or multi-part file")
    pos, attrs = 8, {}
    while True:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        pos = end + 1
        if not name:
            break
        end = data.index(b"\0", pos)
        kind = data[pos:end].decode()
        pos = end + 1
        size = struct.unpack_from("<i", data, pos)[0]
        pos += 4
        attrs[name] = (kind, data[pos:pos + size])
        pos += size
    channels, raw = [], attrs["channels"][1]
    p = 0
    while raw[p] != 0:
        end = raw.index(b"\0", p)
        cname = raw[p:end].decode()
        ptype, _, _, xs, ys = struct.unpack_from("<iB3sii", raw, end + 1)
        if xs != 1 or ys != 1:
            raise Unsupported("subsampled channel " + cname)
        channels.append((cname, ptype))
        p = end + 1 + 16
    compression = attrs["compression"][1][0]
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    return channels, compression, (x0, y0, x1, y1), pos


def _unpredict(buf):
    """ZIP/RLE post-processing: undo the byte predictor, then the two-half interleave."""
    d = np.frombuffer(buf, dtype=np.uint8).astype(np.int64)
    if d.size == 0:
        return b""
    d[1:] -= 128
    t = (np.cumsum(d) & 0xFF).astype(np.uint8)
    half = (t.size + 1) // 2
    out = np.empty_like(t)
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return out.tobytes()


def _unrle(buf, expected):
    out, p = bytearray(), 0
    while p < len(buf):
        n = struct.unpack_from("<b", buf, p)[0]
        p += 1
        if n < 0:
            out += buf[p:p - n]
            p -= n
        else:
            out += buf[p:p + 1] * (n + 1)
            p += 1
    if len(out) != expected:
        raise ValueError("corrupt RLE block")
    return bytes(out)


def _read_plain(path):
    with open(path, "rb") as f:
        data = f.read()
    channels, comp, (x0, y0, x1, y1), pos = _parse_header(data)
    if comp not in _LINES_PER_BLOCK:
        raise Unsupported(f"compression {comp}")
    w, h = x1 - x0 + 1, y1 - y0 + 1
    lines = _LINES_PER_BLOCK[comp]
    nblocks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{nblocks}Q", data, pos)
    channels = sorted(channels)  # the file stores channels in name order
    planes = {name: np.empty((h, w), dtype=np.float64) for name, _ in channels}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        block = data[off + 8:off + 8 + size]
        n = min(lines, y1 - y + 1)
        expected = sum(_DTYPE[t].itemsize for _, t in channels) * w * n
        if size < expected:
            block = _unpredict(zlib.decompress(block) if comp in (_ZIPS, _ZIP) else
                               _unrle(block, expected))
        p = 0
        for row in range(n):
            for name, t in channels:
                dt = _DTYPE[t]
                planes[name][y - y0 + row] = np.frombuffer(block, dtype=dt, count=w, offset=p)
                p += dt.itemsize * w
    return _rgb(planes, path)


def _rgb(planes, path):
    names = {n.split(".")[-1]: n for n in planes}  # "R" or "<layer>.R"
    try:
        return np.stack([planes[names[c]] for c in "RGB"], axis=-1)
    except KeyError:
        raise ValueError(f"{path}: no R, G, B channels (has {sorted(planes)})") from None


def _read_oiio(path):
    import OpenImageIO as oiio  # noqa: N813
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise ValueError(buf.geterror())
    px = np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)
    return px[..., :3]


class _Rgba(ctypes.Structure):
    _fields_ = [("r", ctypes.c_uint16), ("g", ctypes.c_uint16), ("b", ctypes.c_uint16),
                ("a", ctypes.c_uint16)]


def _openexr_c():
    dirs = ["/usr/lib/x86_64-linux-gnu", "/usr/lib64", "/usr/lib", "/usr/local/lib",
            "/opt/homebrew/lib", "/usr/lib/aarch64-linux-gnu"]
    for d in dirs:
        for pattern in ("libOpenEXR-*.so*", "libOpenEXR.so*", "libIlmImf*.so*", "libOpenEXR*.dylib"):
            for lib in sorted(glob.glob(os.path.join(d, pattern))):
                try:
                    so = ctypes.CDLL(lib)
                    so.ImfOpenInputFile  # noqa: B018 — raises AttributeError when absent
                    return so
                except (OSError, AttributeError):
                    continue
    return None


def _read_openexr_c(path):
    so = _openexr_c()
    if so is None:
        raise Unsupported("no OpenEXR shared library with the C API found")
    so.ImfOpenInputFile.restype = ctypes.c_void_p
    so.ImfOpenInputFile.argtypes = [ctypes.c_char_p]
    so.ImfInputHeader.restype = ctypes.c_void_p
    so.ImfInputHeader.argtypes = [ctypes.c_void_p]
    so.ImfHeaderDataWindow.argtypes = [ctypes.c_void_p] + [ctypes.POINTER(ctypes.c_int)] * 4
    so.ImfInputSetFrameBuffer.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t,
                                          ctypes.c_size_t]
    so.ImfInputReadPixels.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_int]
    so.ImfCloseInputFile.argtypes = [ctypes.c_void_p]
    so.ImfErrorMessage.restype = ctypes.c_char_p
    f = so.ImfOpenInputFile(path.encode())
    if not f:
        raise ValueError(f"{path}: {so.ImfErrorMessage().decode()}")
    try:
        win = [ctypes.c_int() for _ in range(4)]
        so.ImfHeaderDataWindow(so.ImfInputHeader(f), *[ctypes.byref(v) for v in win])
        x0, y0, x1, y1 = (v.value for v in win)
        w, h = x1 - x0 + 1, y1 - y0 + 1
        pixels = np.zeros((h, w, 4), dtype=np.float16)
        base = pixels.ctypes.data - (x0 + y0 * w) * 8
        if not so.ImfInputSetFrameBuffer(f, ctypes.c_void_p(base), 1, w) or \
                not so.ImfInputReadPixels(f, y0, y1):
            raise ValueError(f"{path}: {so.ImfErrorMessage().decode()}")
    finally:
        so.ImfCloseInputFile(f)
    return pixels[..., :3].astype(np.float64)


def read_rgb(path):
    """The R, G, B channels of the EXR file `path`, float64 (height, width, 3), row 0 on top."""
    path = os.fspath(path)
    try:
        return _read_oiio(path)
    except ImportError:
        pass
    try:
        return _read_plain(path)
    except Unsupported:
        return _read_openexr_c(path)

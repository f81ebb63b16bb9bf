#!/usr/bin/env python3
"""time_to_error.py — wavepath's time to a given error against peer renderers (issue 15, target 0).

Renders each scene with wavepath and the peers it finds — Mitsuba 3 `scalar_rgb` and
`llvm_ad_rgb`, Blender's Cycles (CPU) — at a ladder of sample counts and several seeds,
measures each image's relMSE against a reference, and reports per renderer the seconds per
spp and the render time needed to reach relMSE 1e-2 and 1e-3, with the ratios wavepath/peer.

Setting (docs/performance.md, "Against other renderers"):
  * scenes: Bitterli's Cornell box (SCENES/cornell-box/scene_v3.xml, 128x128, max_depth 65 =
    64 bounces), Veach's MIS scene (SCENES/veach-mis/scene_v3.xml, 128x72, direct light only:
    wavepath --depth 1, Mitsuba max_depth 2, Cycles 0 bounces) and wavepath's built-in box
    (builtin:cornell-box, 128x96, 64 bounces; written out for the peers by export_builtin.py);
  * box pixel filter everywhere (Mitsuba's rfilter is replaced by `box`);
  * relMSE = mean over pixels and channels of (x - r)^2 / (r^2 + 1e-2), over every pixel but
    the light's edges: a pixel is left out when its 8x8 block at 8x the resolution holds an
    emitter-boundary subpixel (an emitter subpixel with a non-emitter neighbour or the other
    way round, from `wavepath render --depth 0` at 8x the size, 4 spp). There, the shipped
    reference's tent filter (and a tessellated sphere's outline) spreads or moves light;
  * reference: the Cornell box's shipped Mitsuba 3 render (1024^2) box-averaged 8x8 to 128^2;
    the other scenes get one rendered here by Mitsuba (llvm_ad_rgb if it runs, else
    scalar_rgb; else wavepath with a warning) in chunks of --ref-chunk spp until the chunks'
    spread puts the reference's own relMSE under --ref-target (2e-5, 2% of 1e-3) or
    --ref-max-spp is reached; it is cached in the output folder;
  * render time is each renderer's own: wavepath's settings.render_s from --profile (the
    render loop, not process start, scene load or program build); Mitsuba: the time around
    mi.render and the read-back of the image; Cycles: its log's "Render time (without
    synchronization)". Each renderer first renders one untimed warm-up image per scene;
  * order: for each seed, for each spp of the ladder (powers of 2: 4..512 for the Cornell
    box, 4..1024 veach-mis, 8..2048 the built-in box, each bracketing wavepath's 1e-3; or
    --spp), every renderer in turn (the order rotates), so that a change in the machine's
    load spreads over all renderers;
  * time to relMSE E: per seed, linear interpolation of log(relMSE) against log(time) between
    the two ladder levels around E (the first level at or below E); outside the ladder,
    relMSE proportional to 1/time from the nearest level, marked "~". The table gives
    min-max over seeds, the ratios use medians. s per spp: median over seeds of the top
    level's time / spp. "slope": least-squares slope of log relMSE against log spp over the
    upper half of the ladder (-1 for an unbiased estimator; a flatter slope means the
    renderer converges to a different image than the reference); "floor": b of the fit
    relMSE = a/spp + b over the same levels (the reference's own error plus any bias).

Peers are optional: one that is missing is skipped with one line saying why. Nothing in the
build or CI depends on them (scripts/peers/setup.sh installs them).
Mitsuba: a Python that imports mitsuba (--mitsuba-python, else $WP_MITSUBA_PYTHON, else
build/peers/venv/bin/python, else this Python). Its LLVM variant needs libLLVM >= 16
(Debian: libllvm19); found on the usual paths or taken from $DRJIT_LIBLLVM_PATH — LLVM 15
aborts. Cycles: `blender` (--blender, else $WP_BLENDER, else on PATH); Debian's 3.4.1.

Writes OUT/<scene>/ (images while measuring, the reference cache, scene files for the peers),
OUT/results.json (every measurement) and OUT/report.md (the tables, also printed).
"""
import argparse
import datetime
import glob
import hashlib
import json
import math
import os
import platform
import shlex
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

try:
    import numpy as np
except ImportError:
    sys.exit("time_to_error.py needs numpy: run it with a Python that has it (Debian: "
             "python3-numpy; or Mitsuba's venv, build/peers/venv/bin/python)")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # keep the source tree clean
sys.path.insert(0, HERE)
import exrio  # noqa: E402
import export_builtin  # noqa: E402

REPO = os.path.dirname(os.path.dirname(HERE))
EPS = 1e-2
MARK = "@@PEER@@ "
RENDERERS = ["wavepath", "mitsuba-scalar", "mitsuba-llvm", "cycles"]
LABEL = {
    "wavepath": "wavepath",
    "mitsuba-scalar": "Mitsuba 3 `scalar_rgb`",
    "mitsuba-llvm": "Mitsuba 3 `llvm_ad_rgb`",
    "cycles": "Cycles (Blender), CPU",
}
SCENES = ["cornell-box", "veach-mis", "builtin"]
DEFAULT_SIZE = {"cornell-box": (128, 128), "veach-mis": (128, 72), "builtin": (128, 96)}
DEFAULT_DEPTH = {"cornell-box": 64, "veach-mis": 1, "builtin": 64}
DEFAULT_LADDER = {"cornell-box": [2 ** k for k in range(2, 10)],   # 4 .. 512
                  "veach-mis": [2 ** k for k in range(2, 11)],     # 4 .. 1024
                  "builtin": [2 ** k for k in range(3, 12)]}       # 8 .. 2048
MASK_SCALE = 8


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def uptime():
    try:
        with open("/proc/loadavg") as f:
            return "load average " + ", ".join(f.read().split()[:3])
    except OSError:
        return "load average unknown"


# --- images and errors ---------------------------------------------------------------------

def box_down(img, h, w):
    fy, fx = img.shape[0] // h, img.shape[1] // w
    if fy * h != img.shape[0] or fx * w != img.shape[1]:
        raise ValueError(f"reference {img.shape[1]}x{img.shape[0]} is not a multiple of {w}x{h}")
    return img.reshape(h, fy, w, fx, 3).mean(axis=(1, 3))


def relmse(img, ref, keep):
    d = (img - ref) ** 2 / (ref ** 2 + EPS)
    return float(d[keep].mean())


def edge_mask(emission, h, w):
    """True where the 128-scale pixel holds an emitter-boundary subpixel (see the docstring)."""
    lit = emission.sum(axis=-1) > 0
    pad = np.pad(lit, 1, mode="edge")
    hh, ww = lit.shape
    any_n = np.zeros_like(lit)
    all_n = np.ones_like(lit)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            s = pad[dy:dy + hh, dx:dx + ww]
            any_n |= s
            all_n &= s
    boundary = any_n & ~all_n
    fy, fx = hh // h, ww // w
    return boundary.reshape(h, fy, w, fx).any(axis=(1, 3))


# --- workers -------------------------------------------------------------------------------

class WorkerError(Exception):
    pass


def first_line(e):
    lines = str(e).strip().splitlines()
    return lines[0] if lines else type(e).__name__


class Worker:
    """A peer process speaking the JSON-lines protocol of mitsuba_worker.py / cycles_worker.py."""

    def __init__(self, name, argv, env, log_path):
        self.name = name
        self.log = open(log_path, "ab")
        self.proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self.log, env=env, text=True, bufsize=1)
        self.hello = self._read()

    def _read(self):
        while True:
            line = self.proc.stdout.readline()
            if not line:
                code = self.proc.wait()
                hint = (" (Dr.Jit aborts with LLVM 15: point DRJIT_LIBLLVM_PATH at libLLVM >= 16)"
                        if self.name == "mitsuba-llvm" and code == -6 else "")
                raise WorkerError(f"{self.name} exited (status {code}){hint}; see {self.log.name}")
            if line.startswith(MARK):
                return json.loads(line[len(MARK):])
            self.log.write(line.encode(errors="replace"))

    def call(self, **cmd):
        try:
            self.proc.stdin.write(json.dumps(cmd) + "\n")
            self.proc.stdin.flush()
        except BrokenPipeError:
            raise WorkerError(f"{self.name} is gone; see {self.log.name}") from None
        r = self._read()
        if not r.get("ok"):
            raise WorkerError(f"{self.name}: {r.get('error')}\n{r.get('trace', '')}")
        return r

    def close(self):
        if self.proc.poll() is None:
            try:
                self.call(cmd="quit")
            except WorkerError:
                pass
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
        self.log.close()


def find_libllvm():
    env = os.environ.get("DRJIT_LIBLLVM_PATH")
    if env:
        return env, "from $DRJIT_LIBLLVM_PATH"
    found = []
    for d in ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib"] + \
            sorted(glob.glob("/usr/lib/llvm-*/lib")):
        for p in glob.glob(os.path.join(d, "libLLVM*.so*")):
            name = os.path.basename(p)
            digits = "".join(ch if ch.isdigit() else " " for ch in name).split()
            if digits and 16 <= int(digits[0]) < 100:
                found.append((int(digits[0]), p))
    if not found:
        return None, ("no libLLVM >= 16 found (LLVM 15 aborts Dr.Jit); install Debian's "
                      "libllvm19 or set DRJIT_LIBLLVM_PATH")
    found.sort()
    return found[-1][1], f"LLVM {found[-1][0]}"


def mitsuba_python(arg):
    cands = [arg, os.environ.get("WP_MITSUBA_PYTHON"),
             os.path.join(REPO, "build", "peers", "venv", "bin", "python"), sys.executable]
    for c in cands:
        if not c or not (os.path.exists(c) or shutil.which(c)):
            continue
        r = subprocess.run([c, "-c", "import mitsuba, numpy; print(mitsuba.__version__)"],
                           capture_output=True, text=True)
        if r.returncode == 0:
            return c, r.stdout.strip()
    return None, None


# --- renderers -----------------------------------------------------------------------------

class Wavepath:
    name = "wavepath"

    def __init__(self, exe, extra, env):
        self.exe, self.extra, self.env = exe, extra, env
        self.version = subprocess.run([exe, "--version"], capture_output=True, text=True,
                                      env=env).stdout.strip() or "wavepath"

    def describe(self):
        return self.version

    def load(self, scene, work):
        self.scene, self.work = scene, work

    def render(self, spp, seed, out_stem):
        s = self.scene
        exr, prof = out_stem + ".exr", out_stem + ".json"
        cmd = [self.exe, "render", s.wavepath_arg, "--size", f"{s.width}x{s.height}", "--depth",
               str(s.depth), "--spp", str(spp), "--seed", str(seed), "-q", "-o", exr,
               "--profile", prof] + self.extra
        r = subprocess.run(cmd, capture_output=True, text=True, env=self.env)
        if r.returncode != 0:
            raise WorkerError(f"wavepath failed ({r.returncode}): {shlex.join(cmd)}\n{r.stderr}")
        with open(prof) as f:
            p = json.load(f)
        img = exrio.read_rgb(exr)
        for path in (exr, prof, out_stem + ".trace.json"):
            if os.path.exists(path):
                os.remove(path)
        return img, float(p["settings"]["render_s"]), p

    def close(self):
        pass


class MitsubaPeer:
    def __init__(self, name, variant, python, threads, env, log_path):
        self.name, self.variant = name, variant
        self.worker = Worker(name, [python, os.path.join(HERE, "mitsuba_worker.py"), variant,
                                    str(threads)], env, log_path)
        if not self.worker.hello.get("ok"):
            raise WorkerError(self.worker.hello.get("error"))
        self.version = self.worker.hello.get("mitsuba")

    def describe(self):
        return f"Mitsuba {self.version} {self.variant}"

    def load(self, scene, work):
        self.worker.call(cmd="load", xml=scene.mitsuba_xml)

    def render(self, spp, seed, out_stem):
        out = out_stem + ".npy"
        r = self.worker.call(cmd="render", spp=int(spp), seed=int(seed), out=out)
        img = np.load(out).astype(np.float64)
        os.remove(out)
        return img, float(r["render_s"]), r

    def close(self):
        self.worker.close()


class CyclesPeer:
    name = "cycles"

    def __init__(self, blender, threads, env, log_path):
        self.worker = Worker("cycles", [blender, "-b", "--factory-startup", "--debug-cycles",
                                        "--python", os.path.join(HERE, "cycles_worker.py"),
                                        "--", str(threads)], env, log_path)
        self.version = self.worker.hello.get("blender")

    def describe(self):
        return f"Blender {self.version} Cycles"

    def load(self, scene, work):
        if scene.cycles_json is None:
            raise WorkerError(scene.cycles_skip)
        r = self.worker.call(cmd="load", scene=scene.cycles_json)
        self.pattern = r.get("sampling_pattern")

    def render(self, spp, seed, out_stem):
        out = out_stem + ".exr"
        r = self.worker.call(cmd="render", spp=int(spp), seed=int(seed), out=out)
        img = exrio.read_rgb(out)
        os.remove(out)
        return img, float(r["render_s"]), r

    def close(self):
        self.worker.close()


# --- scenes --------------------------------------------------------------------------------

class Scene:
    pass


def read_mtl(path):
    mats, cur = {}, None
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p or p[0].startswith("#"):
                continue
            if p[0] == "newmtl":
                cur = mats.setdefault(p[1], {})
            elif cur is not None:
                cur[p[0]] = [float(x) for x in p[1:]] if len(p) > 1 else []
    return mats


def xml_camera(xml_path):
    sensor = ET.parse(xml_path).getroot().find("sensor")
    fov = float(sensor.find("float[@name='fov']").get("value"))
    axis_el = sensor.find("string[@name='fov_axis']")
    m = [float(x) for x in sensor.find("transform/matrix").get("value").split()]
    return {"to_world": m, "fov": fov, "fov_axis": axis_el.get("value") if axis_el is not None else "x"}


def xml_bsdfs(xml_path):
    """id -> the innermost BSDF element (through twosided)."""
    root = ET.parse(xml_path).getroot()
    out = {}
    for b in root.findall("bsdf"):
        inner = b
        while inner.get("type") == "twosided":
            inner = inner.find("bsdf")
        out[b.get("id")] = inner
    return out


def rgb_of(el, name):
    e = el.find(f"rgb[@name='{name}']")
    if e is None:
        return None
    v = [float(x) for x in e.get("value").replace(",", " ").split()]
    return v * 3 if len(v) == 1 else v


def cycles_materials_from_xml(xml_path, mtl_path):
    """Cycles materials for the OBJ's `usemtl` names: emission from the MTL's Ke, the rest
    from the XML's BSDF "<name>BSDF" (diffuse, Beckmann roughconductor)."""
    bsdfs = xml_bsdfs(xml_path)
    mats = {}
    for name, m in read_mtl(mtl_path).items():
        b = bsdfs.get(name + "BSDF")
        if any(m.get("Ke", [0])):
            mats[name] = {"type": "emitter", "radiance": m["Ke"]}
        elif b is not None and b.get("type") == "diffuse":
            mats[name] = {"type": "diffuse", "color": rgb_of(b, "reflectance")}
        elif b is not None and b.get("type") == "roughconductor":
            dist = b.find("string[@name='distribution']")
            if dist is None or dist.get("value") != "beckmann":
                raise ValueError(f"{xml_path}: {name}: only Beckmann conductors are mapped")
            mats[name] = {"type": "beckmann_conductor",
                          "alpha": float(b.find("float[@name='alpha']").get("value")),
                          "eta": rgb_of(b, "eta"), "k": rgb_of(b, "k"),
                          "scale": rgb_of(b, "specular_reflectance") or [1.0] * 3}
        else:
            raise ValueError(f"{xml_path}: no Cycles mapping for material {name}")
    return mats


def write_mitsuba_xml(src, dst, width, height, depth):
    """src with the film at width x height, a box rfilter and max_depth = depth + 1."""
    tree = ET.parse(src)
    root = tree.getroot()
    base = os.path.dirname(os.path.abspath(src))
    for s in root.iter("string"):
        if s.get("name") == "filename" and not os.path.isabs(s.get("value")):
            s.set("value", os.path.join(base, s.get("value")))
    film = root.find("sensor/film")
    for name, value in (("width", width), ("height", height)):
        e = film.find(f"integer[@name='{name}']")
        if e is None:
            e = ET.SubElement(film, "integer", name=name)
        e.set("value", str(value))
    for rf in film.findall("rfilter"):
        film.remove(rf)
    ET.SubElement(film, "rfilter", type="box")
    integ = root.find("integrator")
    if integ is None:
        integ = ET.SubElement(root, "integrator", type="path")
    md = integ.find("integer[@name='max_depth']")
    if md is None:
        md = ET.SubElement(integ, "integer", name="max_depth")
    md.set("value", str(depth + 1))
    tree.write(dst)


def setup_scene(key, args, work):
    s = Scene()
    s.key = key
    s.width, s.height = args.size or DEFAULT_SIZE[key]
    s.depth = args.depth if args.depth is not None else DEFAULT_DEPTH[key]
    s.cycles_json, s.cycles_skip = None, None
    s.ref_path = None
    cyc = None
    if key == "cornell-box":
        d = os.path.join(args.scenes_dir, "cornell-box")
        s.xml = os.path.join(d, "scene_v3.xml")
        if not os.path.exists(s.xml):
            raise FileNotFoundError(f"{s.xml} not found (--scenes-dir {args.scenes_dir})")
        s.wavepath_arg = s.xml
        s.ref_path = os.path.join(d, "reference", "Mitsuba3Render.exr")
        mats = {}
        for name, m in read_mtl(os.path.join(d, "cornell-box.mtl")).items():
            if any(m.get("Ke", [0])):
                mats[name] = {"type": "emitter", "radiance": m["Ke"]}
            else:
                mats[name] = {"type": "diffuse", "color": m["Kd"]}
        cyc = {"obj": os.path.join(d, "cornell-box.obj"), "materials": mats,
               "camera": xml_camera(s.xml)}
        s.title = "Bitterli's Cornell box (cornell-box/scene_v3.xml)"
    elif key == "veach-mis":
        d = os.path.join(args.scenes_dir, "veach-mis")
        s.xml = os.path.join(d, "scene_v3.xml")
        if not os.path.exists(s.xml):
            raise FileNotFoundError(f"{s.xml} not found (--scenes-dir {args.scenes_dir})")
        s.wavepath_arg = s.xml
        try:
            cyc = {"obj": os.path.join(d, "veach-mis.obj"), "camera": xml_camera(s.xml),
                   "materials": cycles_materials_from_xml(s.xml, os.path.join(d, "veach-mis.mtl"))}
        except (ValueError, OSError) as e:
            s.cycles_skip = f"no Cycles version of this scene: {e}"
        s.title = "Veach's MIS scene (veach-mis/scene_v3.xml), direct light"
    elif key == "builtin":
        desc = export_builtin.export(os.path.join(work, "export"), s.width, s.height, s.depth)
        s.xml = desc["xml"]
        s.wavepath_arg = "builtin:cornell-box"
        s.export_triangles = desc["triangles"]
        cyc = {"obj": desc["obj"], "materials": desc["materials"], "camera": desc["camera"]}
        s.title = "wavepath's built-in box (builtin:cornell-box)"
    else:
        raise ValueError(f"unknown scene {key!r} (known: {', '.join(SCENES)})")
    s.mitsuba_xml = os.path.join(work, "mitsuba.xml")
    write_mitsuba_xml(s.xml, s.mitsuba_xml, s.width, s.height, s.depth)
    if cyc is not None:
        cyc.update({"width": s.width, "height": s.height, "bounces": max(0, s.depth - 1)})
        s.cycles_json = os.path.join(work, "cycles.json")
        with open(s.cycles_json, "w") as f:
            json.dump(cyc, f, indent=1)
    return s


def light_mask(scene, wp, work):
    """(True for the pixels kept, wavepath's triangle count from its profile)."""
    stem = os.path.join(work, "emission")
    exr, prof = stem + ".exr", stem + ".json"
    cmd = [wp.exe, "render", scene.wavepath_arg, "--size",
           f"{MASK_SCALE * scene.width}x{MASK_SCALE * scene.height}", "--depth", "0", "--spp", "4",
           "--seed", "7", "-q", "-o", exr, "--profile", prof]
    r = subprocess.run(cmd, capture_output=True, text=True, env=wp.env)
    if r.returncode != 0:
        raise WorkerError(f"wavepath failed: {shlex.join(cmd)}\n{r.stderr}")
    with open(prof) as f:
        tris = json.load(f)["scene"]["triangles"]
    emission = exrio.read_rgb(exr)
    return ~edge_mask(emission, scene.height, scene.width), tris


# --- reference -----------------------------------------------------------------------------

def file_digest(paths):
    h = hashlib.sha256()
    for p in paths:
        with open(p, "rb") as f:
            h.update(f.read())
    return h.hexdigest()[:16]


def make_reference(scene, peers, wp, args, work, keep):
    """(reference image, description, own relMSE or None)."""
    if scene.ref_path:
        full = exrio.read_rgb(scene.ref_path)
        ref = box_down(full, scene.height, scene.width)
        f = full.shape[0] // scene.height
        note = (f"the shipped {os.path.relpath(scene.ref_path, args.scenes_dir)} "
                f"({full.shape[1]}x{full.shape[0]}), box-averaged {f}x{f}")
        own = None
        other = os.path.join(os.path.dirname(scene.ref_path), "TungstenRender.exr")
        if os.path.exists(other):
            t = box_down(exrio.read_rgb(other), scene.height, scene.width)
            own = relmse(t, ref, keep)
            note += (f"; relMSE of the shipped Tungsten reference against it: {own:.2e} (an "
                     f"upper bound of the reference's own error, plus any difference of the two "
                     f"renderers)")
        return ref, note, None
    order = {"auto": ["mitsuba-llvm", "mitsuba-scalar", "wavepath"]}.get(
        args.ref_renderer, [args.ref_renderer])
    cands = [n for n in order if n in peers or n == "wavepath"]
    key = {"chunk": args.ref_chunk, "target": args.ref_target, "max_spp": args.ref_max_spp,
           "size": [scene.width, scene.height], "depth": scene.depth,
           "files": file_digest([scene.mitsuba_xml])}
    cache_img, cache_meta = os.path.join(work, "reference.npy"), os.path.join(work, "reference.json")
    if os.path.exists(cache_img) and os.path.exists(cache_meta):
        with open(cache_meta) as f:
            meta = json.load(f)
        cached = dict(meta.get("key", {}))
        if cached.pop("renderer", None) in cands and cached == key:
            log(f"  reference: cached {cache_img}")
            return np.load(cache_img), meta["note"], meta.get("own_relmse")
    for chosen in cands:
        try:
            return render_reference(scene, peers[chosen] if chosen != "wavepath" else wp,
                                    args, work, keep, key | {"renderer": chosen},
                                    cache_img, cache_meta)
        except WorkerError as e:
            if chosen == "wavepath":
                raise
            log(f"  reference: {chosen} failed ({first_line(e)}); trying the next")
    raise WorkerError("no renderer could render the reference")


def render_reference(scene, r, args, work, keep, key, cache_img, cache_meta):
    if r.name == "wavepath":
        log("  WARNING: no Mitsuba to render the reference: wavepath renders its own (other "
            "seeds). Its error then shows only wavepath's variance, not a bias.")
    r.load(scene, work)
    log(f"  reference: {r.describe()}, chunks of {args.ref_chunk} spp until its own relMSE "
        f"<= {args.ref_target:g} or {args.ref_max_spp} spp ...")
    t0 = time.time()
    mean = m2 = None
    n, own = 0, float("inf")
    while n < 4 or (own > args.ref_target and (n + 1) * args.ref_chunk <= args.ref_max_spp):
        img, _, _ = r.render(args.ref_chunk, 1_000_000 + n, os.path.join(work, f"ref{n}"))
        n += 1
        if mean is None:
            mean, m2 = np.zeros_like(img), np.zeros_like(img)
        d = img - mean
        mean += d / n
        m2 += d * (img - mean)
        if n >= 2:
            var_of_mean = m2 / (n - 1) / n
            own = float((var_of_mean / (mean ** 2 + EPS))[keep].mean())
        if n % 8 == 0:
            log(f"    {n * args.ref_chunk} spp: own relMSE {own:.1e}")
    note = (f"rendered here by {r.describe()}, {n * args.ref_chunk} spp ({n} chunks of "
            f"{args.ref_chunk}, {time.time() - t0:.0f} s); its own relMSE from the chunks' "
            f"spread: {own:.1e}")
    if r.name == "wavepath":
        note += (" — WARNING: no Mitsuba ran, so wavepath's own image is the reference: the "
                 "errors show wavepath's variance, not a bias, and the peers' bias counts "
                 "against them")
    if own > args.ref_target:
        note += f" (above --ref-target {args.ref_target:g}: --ref-max-spp stopped it)"
    np.save(cache_img, mean)
    with open(cache_meta, "w") as f:
        json.dump({"key": key, "note": note, "own_relmse": own}, f, indent=1)
    return mean, note, own


# --- fitting -------------------------------------------------------------------------------

def time_to(points, target):
    """points: [(spp, time, relmse)] sorted by spp -> (time, extrapolated?)."""
    pts = [(t, e) for _, t, e in points if t > 0 and e > 0]
    if not pts:
        return None, True
    for i, (t, e) in enumerate(pts):
        if e <= target:
            if i == 0:
                return t * e / target, True
            t0, e0 = pts[i - 1]
            if e0 == e:
                return t, False
            lt = math.log(t0) + (math.log(target) - math.log(e0)) * \
                (math.log(t) - math.log(t0)) / (math.log(e) - math.log(e0))
            return math.exp(lt), False
    t, e = pts[-1]
    return t * e / target, True


def fit_upper(points):
    """(slope of log relMSE vs log spp, floor b of relMSE = a/spp + b) over the upper half."""
    pts = sorted(points)[min(len(points) // 2, max(0, len(points) - 2)):]
    if len(pts) < 2:
        return None, None
    x = np.log([p[0] for p in pts])
    y = np.log([p[2] for p in pts])
    slope = float(np.polyfit(x, y, 1)[0])
    A = np.stack([1.0 / np.array([p[0] for p in pts], dtype=float), np.ones(len(pts))], axis=1)
    a, b = np.linalg.lstsq(A, np.array([p[2] for p in pts]), rcond=None)[0]
    return slope, float(b)


def fmt_s(v):
    if v is None:
        return "–"
    return f"{v:.3g}" if v < 100 else f"{v:.0f}"


def fmt_range(vals):
    xs = [v for v, _ in vals if v is not None]
    if not xs:
        return "–"
    tilde = "~" if any(x for _, x in vals) else ""
    lo, hi = min(xs), max(xs)
    if fmt_s(lo) == fmt_s(hi):
        return f"{tilde}{fmt_s(lo)} s"
    return f"{tilde}{fmt_s(lo)}–{fmt_s(hi)} s"


def summarize(scene, results, renderers, targets):
    rows, med = [], {}
    for name in renderers:
        by_seed = {}
        for r in results:
            if r["renderer"] == name:
                by_seed.setdefault(r["seed"], []).append((r["spp"], r["render_s"], r["relmse"]))
        if not by_seed:
            continue
        for pts in by_seed.values():
            pts.sort()
        top = [pts[-1][1] / pts[-1][0] for pts in by_seed.values()]
        cells, med[name] = [], {}
        for tgt in targets:
            vals = [time_to(pts, tgt) for pts in by_seed.values()]
            cells.append(fmt_range(vals))
            xs = [v for v, _ in vals if v is not None]
            med[name][tgt] = float(np.median(xs)) if xs else None
        all_pts = [p for pts in by_seed.values() for p in pts]
        slopes = [fit_upper(pts) for pts in by_seed.values()]
        ss = [s for s, _ in slopes if s is not None]
        bs = [b for _, b in slopes if b is not None]
        slope = float(np.median(ss)) if ss else None
        floor = float(np.median(bs)) if bs else None
        top_spp = max(p[0] for p in all_pts)
        top_err = np.median([p[2] for p in all_pts if p[0] == top_spp])
        rows.append([LABEL[name], f"{np.median(top):.4f}"] + cells +
                    [f"{top_err:.2e} @ {top_spp}", f"{slope:.2f}" if slope is not None else "–",
                     f"{floor:.1e}" if floor is not None else "–"])
    head = ["renderer", "s per spp"] + [f"time to relMSE {t:g}" for t in targets] + \
        ["relMSE at top spp", "slope", "floor"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    if "wavepath" in med and len(med) > 1:
        lines += ["", "| wavepath / peer (medians over seeds) | " +
                  " | ".join(f"time to {t:g}" for t in targets) + " |",
                  "|---|" + "---|" * len(targets)]
        for name in renderers:
            if name == "wavepath" or name not in med:
                continue
            cells = []
            for t in targets:
                a, b = med["wavepath"].get(t), med[name].get(t)
                cells.append(f"{a / b:.2f}×" if a and b else "–")
            lines.append(f"| {LABEL[name]} | " + " | ".join(cells) + " |")
    return lines


# --- main ----------------------------------------------------------------------------------

def default_scenes_dir():
    if os.environ.get("WP_SHARED_SCENES"):
        return os.environ["WP_SHARED_SCENES"]
    cands = [os.path.join(os.path.dirname(REPO), "shared", "scenes")]
    r = subprocess.run(["git", "-C", REPO, "rev-parse", "--path-format=absolute",
                        "--git-common-dir"], capture_output=True, text=True)
    if r.returncode == 0 and r.stdout.strip():  # a worktree: next to the main checkout
        main = os.path.dirname(r.stdout.strip())
        cands.append(os.path.join(os.path.dirname(main), "shared", "scenes"))
    return next((c for c in cands if os.path.isdir(c)), cands[0])


def parse_size(s):
    w, h = s.lower().split("x")
    return int(w), int(h)


def main():
    ap = argparse.ArgumentParser(
        description="Time to relMSE 1e-2 and 1e-3 of wavepath and peer renderers (Mitsuba 3 "
                    "scalar/LLVM, Blender Cycles) on the same scenes; see the module docstring "
                    "and docs/performance.md, 'Against other renderers'.",
        epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default=",".join(SCENES),
                    help="comma-separated, from: %(default)s")
    ap.add_argument("--renderers", default=",".join(RENDERERS),
                    help="comma-separated, from: %(default)s (wavepath is always rendered)")
    ap.add_argument("--seeds", type=int, default=3, help="seeds 1..N per renderer (default 3)")
    ap.add_argument("--spp", default=None,
                    help="the spp ladder for every scene, e.g. 4,16,64 (default: powers of 2, "
                         + "; ".join(f"{k} {v[0]}..{v[-1]}" for k, v in DEFAULT_LADDER.items())
                         + ": each brackets relMSE 1e-3 for wavepath)")
    ap.add_argument("--out", default=os.path.join(REPO, "build", "peers"),
                    help="output folder (default build/peers in the repository)")
    ap.add_argument("--scenes-dir", default=default_scenes_dir(),
                    help="the shared scenes (default $WP_SHARED_SCENES, else ../shared/scenes "
                         "next to the repository or to its main worktree)")
    ap.add_argument("--wavepath", default=os.path.join(REPO, "build", "release", "wavepath"),
                    help="the wavepath binary (default build/release/wavepath)")
    ap.add_argument("--wavepath-args", default="",
                    help="extra arguments for every wavepath render, e.g. '--traversal stack'")
    ap.add_argument("--mitsuba-python", default=None,
                    help="a Python that imports mitsuba (else $WP_MITSUBA_PYTHON, "
                         "build/peers/venv/bin/python, this Python)")
    ap.add_argument("--blender", default=os.environ.get("WP_BLENDER", "blender"),
                    help="Blender executable (default $WP_BLENDER or blender)")
    ap.add_argument("--threads", type=int, default=2,
                    help="threads for Mitsuba and Cycles (default 2; wavepath uses its OpenCL "
                         "device as it is)")
    ap.add_argument("--size", type=parse_size, default=None,
                    help="WxH for every scene (default 128x128, 128x72, 128x96)")
    ap.add_argument("--depth", type=int, default=None,
                    help="wavepath depth for every scene (default 64, 1, 64); Mitsuba gets "
                         "max_depth = depth + 1, Cycles depth - 1 bounces")
    ap.add_argument("--ref-target", type=float, default=2e-5,
                    help="rendered references: add chunks until their own relMSE (from the "
                         "chunks' spread) is at most this (default %(default)g)")
    ap.add_argument("--ref-max-spp", type=int, default=65536,
                    help="rendered references: at most this many spp (default %(default)s)")
    ap.add_argument("--ref-chunk", type=int, default=512,
                    help="spp per reference chunk (default %(default)s)")
    ap.add_argument("--ref-renderer", default="auto",
                    choices=["auto", "mitsuba-llvm", "mitsuba-scalar", "wavepath"],
                    help="who renders the references (auto: LLVM, else scalar, else wavepath)")
    ap.add_argument("--targets", default="1e-2,1e-3", help="relMSE targets (default %(default)s)")
    args = ap.parse_args()

    scenes = [s for s in args.scenes.split(",") if s]
    for s in scenes:
        if s not in SCENES:
            ap.error(f"unknown scene {s!r} (known: {', '.join(SCENES)})")
    wanted = [r for r in args.renderers.split(",") if r]
    for r in wanted:
        if r not in RENDERERS:
            ap.error(f"unknown renderer {r!r} (known: {', '.join(RENDERERS)})")
    fixed_ladder = sorted({int(x) for x in args.spp.split(",")}) if args.spp else None
    targets = [float(x) for x in args.targets.split(",")]
    seeds = list(range(1, args.seeds + 1))
    if not os.access(args.wavepath, os.X_OK):
        ap.error(f"--wavepath {args.wavepath} is not an executable (build it: cmake --build "
                 f"--preset release --target wavepath)")
    os.makedirs(args.out, exist_ok=True)
    log_path = os.path.join(args.out, "peers.log")
    started = time.time()
    load_before = uptime()
    log(f"time_to_error: {load_before}")

    env = dict(os.environ)
    env.setdefault("POCL_CACHE_DIR", os.path.join(os.path.dirname(args.wavepath), "pocl-cache"))
    wp = Wavepath(args.wavepath, shlex.split(args.wavepath_args), env)
    peers, skipped = {}, {}
    mpy, mver = None, None
    if any(r.startswith("mitsuba") for r in wanted):
        mpy, mver = mitsuba_python(args.mitsuba_python)
    for name in wanted:
        if name == "wavepath":
            continue
        try:
            if name.startswith("mitsuba"):
                if mpy is None:
                    raise WorkerError("no Python that imports mitsuba (pip install mitsuba; "
                                      "--mitsuba-python or $WP_MITSUBA_PYTHON)")
                penv = dict(env)
                if name == "mitsuba-llvm":
                    lib, why = find_libllvm()
                    if lib is None:
                        raise WorkerError(why)
                    penv["DRJIT_LIBLLVM_PATH"] = lib
                variant = "llvm_ad_rgb" if name == "mitsuba-llvm" else "scalar_rgb"
                peers[name] = MitsubaPeer(name, variant, mpy, args.threads, penv, log_path)
            elif name == "cycles":
                if not shutil.which(args.blender):
                    raise WorkerError(f"no `{args.blender}` on PATH (Debian: apt-get install "
                                      f"blender; or --blender)")
                peers[name] = CyclesPeer(args.blender, args.threads, env, log_path)
        except WorkerError as e:
            skipped[name] = first_line(e)
            log(f"skipping {name}: {skipped[name]}")
    renderers = ["wavepath"] + [r for r in RENDERERS if r in peers]
    all_results, report = [], []
    report += ["# Time to error: wavepath against peer renderers", "",
               f"{datetime.datetime.now().isoformat(timespec='seconds')}, {platform.node()}, "
               f"{os.cpu_count()} CPUs; {load_before} at the start.",
               f"Seeds {seeds[0]}..{seeds[-1]}; relMSE with eps {EPS:g}, light-edge pixels masked. Peers with {args.threads} "
               f"threads.", ""]
    report += [f"- {wp.describe()}" + (f" (extra: {args.wavepath_args})" if args.wavepath_args else "")]
    report += [f"- {p.describe()}" for p in peers.values()]
    report += [f"- {n}: skipped — {why}" for n, why in skipped.items()]
    report.append("")

    try:
        for key in scenes:
            work = os.path.join(args.out, key)
            ladder = fixed_ladder or DEFAULT_LADDER[key]
            os.makedirs(work, exist_ok=True)
            try:
                scene = setup_scene(key, args, work)
            except FileNotFoundError as e:
                log(f"{key}: skipped: {e}")
                report += [f"## {key}", "", f"Skipped: {e}.", ""]
                continue
            log(f"{key}: {scene.width}x{scene.height}, depth {scene.depth}")
            keep, wp_tris = light_mask(scene, wp, work)
            notes = []
            if key == "builtin" and wp_tris != scene.export_triangles:
                notes.append(f"WARNING: export_builtin.py wrote {scene.export_triangles} "
                             f"triangles, wavepath has {wp_tris}: the exported box is out of "
                             f"step with src/scene/builtin.cpp; peers skipped for this scene")
                log(notes[-1])
            scene_peers = {} if notes else dict(peers)
            usable = {}
            for name, p in scene_peers.items():
                try:
                    p.load(scene, work)
                    usable[name] = p
                except WorkerError as e:
                    notes.append(f"{name} skipped for this scene: {first_line(e)}")
                    log(notes[-1])
            ref, ref_note, _ = make_reference(scene, usable, wp, args, work, keep)
            wp.load(scene, work)
            order = ["wavepath"] + [r for r in renderers if r in usable]
            objs = {"wavepath": wp, **usable}
            for name in list(order):  # warm-up, untimed
                try:
                    objs[name].render(ladder[0], 999, os.path.join(work, f"warm-{name}"))
                except WorkerError as e:
                    if name == "wavepath":
                        raise
                    notes.append(f"{name} skipped: {first_line(e)}")
                    log(notes[-1])
                    order.remove(name)
                    usable.pop(name)
            results = []
            k = 0
            for seed in seeds:
                for spp in ladder:
                    rot = order[k % len(order):] + order[:k % len(order)]
                    k += 1
                    for name in rot:
                        try:
                            img, t, _ = objs[name].render(spp, seed,
                                                          os.path.join(work, f"{name}-{seed}-{spp}"))
                        except WorkerError as e:
                            if name == "wavepath":
                                raise
                            notes.append(f"{name} failed and was dropped: {first_line(e)}")
                            log(notes[-1])
                            order.remove(name)
                            continue
                        e = relmse(img, ref, keep)
                        rec = {"scene": key, "renderer": name, "seed": seed, "spp": spp,
                               "render_s": t, "relmse": e}
                        results.append(rec)
                        log(f"  seed {seed} spp {spp:5d} {name:15s} {t:8.3f} s  relMSE {e:.3e}")
            all_results += results
            masked = int((~keep).sum())
            report += [f"## {scene.title}", "",
                       f"{scene.width}x{scene.height}, wavepath depth {scene.depth} "
                       f"(Mitsuba max_depth {scene.depth + 1}, Cycles {max(0, scene.depth - 1)} "
                       f"bounces); spp ladder {', '.join(map(str, ladder))}; {masked} light-edge "
                       f"pixels of {keep.size} masked. "
                       f"Reference: {ref_note}.", ""]
            report += summarize(scene, results, [r for r in renderers if r == "wavepath" or r in usable],
                                targets)
            report += [""] + [f"- {n}" for n in notes] + ([""] if notes else [])
            with open(os.path.join(args.out, "results.json"), "w") as f:
                json.dump(all_results, f, indent=1)
    finally:
        for p in peers.values():
            p.close()
    report += [f"Wall time of this run: {time.time() - started:.0f} s; {uptime()} at the end.",
               "Ranges are min–max over seeds; \"~\": extrapolated beyond the ladder with "
               "relMSE ∝ 1/time."]
    text = "\n".join(report) + "\n"
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()

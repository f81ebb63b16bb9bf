"""cycles_worker.py — renders for time_to_error.py with Blender's Cycles (CPU).

Run by time_to_error.py as
    blender -b --factory-startup --debug-cycles --python cycles_worker.py -- THREADS
Cycles cannot read Mitsuba XML, so the driver hands over a scene description (JSON): one OBJ
file whose `usemtl` groups name the materials, the materials themselves, the camera as
Mitsuba's to_world matrix with its fov, the image size and the bounce limit. Reads one JSON
command a line on stdin and answers each with one line "@@PEER@@ {json}" on stdout
(Blender's own output goes around it):
  {"cmd": "load", "scene": PATH.json}             -> {"ok": true, "triangles": N, ...}
  {"cmd": "render", "spp": N, "seed": S, "out": PATH.exr}
        -> {"ok": true, "render_s": Cycles' own "Render time (without synchronization)",
            "total_s": the time around bpy.ops.render.render}
  {"cmd": "quit"}

Settings (the issue's): CPU, THREADS threads, every bounce limit (total, diffuse, glossy,
transmission, volume, transparent) = "bounces", clamping off (direct and indirect 0), no
denoising, no adaptive sampling, Filter Glossy 0 (its default 1 blurs glossy paths: a bias),
box pixel filter 1 px wide, black world, one-sided emitters (emission times "not
backfacing"). Cycles counts bounces after the first hit (0 = direct light only), so the
driver passes wavepath's depth - 1.

Materials ("type"):
  diffuse    {"color"}                  Diffuse BSDF
  emitter    {"radiance"}               Emission (strength 1: radiance), front side only
  mirror     {"color"}                  Glossy BSDF, Sharp
  ggx_schlick {"f0", "alpha"}           Glossy BSDF, GGX, roughness sqrt(alpha), colour =
                                        Schlick's Fresnel of the shading normal's cosine
  beckmann_conductor {"alpha", "eta", "k", "scale"}
                                        Glossy BSDF, Beckmann, roughness sqrt(alpha), colour =
                                        scale x the conductor Fresnel of the shading normal's
                                        cosine (math nodes per channel)
Cycles' Glossy BSDF has no Fresnel of its own, and a node graph cannot see the microfacet
normal: the Fresnel factor uses the angle to the shading normal instead of the half vector
(Mitsuba and wavepath use the half vector). The difference is small for these roughnesses;
the driver's check of Cycles' converged error shows it where it is not.
"""
import json
import math
import os
import re
import sys
import tempfile
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from worker_protocol import reply, serve  # noqa: E402


# --- geometry ------------------------------------------------------------------------------

def read_obj(path):
    """Groups of triangles by (material, has normals): {key: (positions, normals or None)}."""
    v, vn, groups, mat = [], [], {}, "default"
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            tag = parts[0]
            if tag == "v":
                v.append(tuple(float(x) for x in parts[1:4]))
            elif tag == "vn":
                vn.append(tuple(float(x) for x in parts[1:4]))
            elif tag == "usemtl":
                mat = parts[1]
            elif tag == "f":
                corners = []
                for c in parts[1:]:
                    idx = c.split("/")
                    pi = int(idx[0])
                    ni = int(idx[2]) if len(idx) > 2 and idx[2] else 0
                    corners.append((pi - 1 if pi > 0 else len(v) + pi,
                                    (ni - 1 if ni > 0 else len(vn) + ni) if ni else None))
                smooth = all(c[1] is not None for c in corners)
                pos, nrm = groups.setdefault((mat, smooth), ([], [] if smooth else None))
                for k in range(1, len(corners) - 1):  # fan triangulation
                    for c in (corners[0], corners[k], corners[k + 1]):
                        pos.append(v[c[0]])
                        if smooth:
                            nrm.append(vn[c[1]])
    return groups


def add_mesh(name, positions, normals, material):
    n = len(positions) // 3
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(positions, [], [(3 * i, 3 * i + 1, 3 * i + 2) for i in range(n)])
    mesh.materials.append(material)
    if normals is not None:
        for p in mesh.polygons:
            p.use_smooth = True
        mesh.use_auto_smooth = True  # needed for custom split normals (Blender < 4.1)
        mesh.normals_split_custom_set(normals)
    else:
        for p in mesh.polygons:
            p.use_smooth = False
    mesh.validate()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return n


# --- materials -----------------------------------------------------------------------------

class Nodes:
    def __init__(self, mat):
        mat.use_nodes = True
        self.nt = mat.node_tree
        self.nt.nodes.clear()
        self.out = self.nt.nodes.new("ShaderNodeOutputMaterial")

    def node(self, kind, **inputs):
        n = self.nt.nodes.new(kind)
        for key, value in inputs.items():
            self.set(n.inputs[key], value)
        return n

    def set(self, socket, value):
        if isinstance(value, bpy.types.NodeSocket):
            self.nt.links.new(value, socket)
        else:
            socket.default_value = value

    def math(self, op, a, b=0.0):
        n = self.nt.nodes.new("ShaderNodeMath")
        n.operation = op
        self.set(n.inputs[0], a)
        self.set(n.inputs[1], b)
        return n.outputs[0]

    def cos_theta(self):
        """|N . I| of the shading normal: 1 - Layer Weight's Facing at blend 0.5."""
        lw = self.node("ShaderNodeLayerWeight", Blend=0.5)
        return self.math("SUBTRACT", 1.0, lw.outputs["Facing"])

    def rgb(self, r, g, b):
        n = self.nt.nodes.new("ShaderNodeCombineRGB")
        for i, c in enumerate((r, g, b)):
            self.set(n.inputs[i], c)
        return n.outputs[0]


def fresnel_conductor(nb, c, eta, k):
    """Unpolarised Fresnel reflectance of a conductor (eta, k) at cosine c (a socket)."""
    m = nb.math
    c2 = m("MULTIPLY", c, c)
    s2 = m("SUBTRACT", 1.0, c2)
    t0 = m("SUBTRACT", eta * eta - k * k, s2)
    a2pb2 = m("SQRT", m("ADD", m("MULTIPLY", t0, t0), 4.0 * eta * eta * k * k))
    a = m("SQRT", m("MULTIPLY", m("ADD", a2pb2, t0), 0.5))
    t1 = m("ADD", a2pb2, c2)
    t2 = m("MULTIPLY", m("MULTIPLY", a, c), 2.0)
    rs = m("DIVIDE", m("SUBTRACT", t1, t2), m("ADD", t1, t2))
    t3 = m("ADD", m("MULTIPLY", c2, a2pb2), m("MULTIPLY", s2, s2))
    t4 = m("MULTIPLY", t2, s2)
    rp = m("MULTIPLY", rs, m("DIVIDE", m("SUBTRACT", t3, t4), m("ADD", t3, t4)))
    return m("MULTIPLY", m("ADD", rs, rp), 0.5)


def make_material(name, spec):
    mat = bpy.data.materials.new(name)
    nb = Nodes(mat)
    kind = spec["type"]
    rgba = lambda c: (c[0], c[1], c[2], 1.0)  # noqa: E731
    if kind == "diffuse":
        shader = nb.node("ShaderNodeBsdfDiffuse", Color=rgba(spec["color"]), Roughness=0.0)
    elif kind == "emitter":
        emit = nb.node("ShaderNodeEmission", Color=rgba(spec["radiance"]), Strength=1.0)
        geo = nb.node("ShaderNodeNewGeometry")
        black = nb.node("ShaderNodeBsdfDiffuse", Color=(0.0, 0.0, 0.0, 1.0))
        mix = nb.node("ShaderNodeMixShader", Fac=geo.outputs["Backfacing"])
        nb.set(mix.inputs[1], emit.outputs[0])
        nb.set(mix.inputs[2], black.outputs[0])
        shader = mix
    elif kind == "mirror":
        shader = nb.node("ShaderNodeBsdfGlossy", Color=rgba(spec["color"]), Roughness=0.0)
        shader.distribution = "SHARP"
    elif kind == "ggx_schlick":
        w = nb.math("POWER", nb.math("SUBTRACT", 1.0, nb.cos_theta()), 5.0)
        mix = nb.node("ShaderNodeMixRGB", Fac=w, Color1=rgba(spec["f0"]),
                      Color2=(1.0, 1.0, 1.0, 1.0))
        shader = nb.node("ShaderNodeBsdfGlossy", Color=mix.outputs[0],
                         Roughness=math.sqrt(spec["alpha"]))
        shader.distribution = "GGX"
    elif kind == "beckmann_conductor":
        c = nb.cos_theta()
        ch = [nb.math("MULTIPLY", fresnel_conductor(nb, c, spec["eta"][i], spec["k"][i]),
                      spec["scale"][i]) for i in range(3)]
        shader = nb.node("ShaderNodeBsdfGlossy", Color=nb.rgb(*ch),
                         Roughness=math.sqrt(spec["alpha"]))
        shader.distribution = "BECKMANN"
    else:
        raise ValueError(f"material {name}: unknown type {kind!r}")
    nb.set(nb.out.inputs["Surface"], shader.outputs[0])
    return mat


# --- scene ---------------------------------------------------------------------------------

def setup_render(desc, threads):
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    b = int(desc["bounces"])
    cy.max_bounces = b
    cy.diffuse_bounces = b
    cy.glossy_bounces = b
    cy.transmission_bounces = b
    cy.volume_bounces = b
    cy.transparent_max_bounces = b
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    cy.use_animated_seed = False
    sc.render.threads_mode = "FIXED"
    sc.render.threads = threads
    sc.render.resolution_x = int(desc["width"])
    sc.render.resolution_y = int(desc["height"])
    sc.render.resolution_percentage = 100
    sc.render.film_transparent = False
    sc.render.use_persistent_data = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    world = bpy.data.worlds.new("black")
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    sc.world = world


def setup_camera(cam_desc, width, height):
    m = cam_desc["to_world"]  # Mitsuba: looks down +z, +x is left, +y up
    # Blender's camera looks down -z with +x right: flip x and z.
    rows = [[-m[4 * r + 0], m[4 * r + 1], -m[4 * r + 2], m[4 * r + 3]] for r in range(3)]
    rows.append([0.0, 0.0, 0.0, 1.0])
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    axis = cam_desc.get("fov_axis", "x")
    if axis == "smaller":
        axis = "x" if width <= height else "y"
    elif axis == "larger":
        axis = "x" if width >= height else "y"
    cam.sensor_fit = "HORIZONTAL" if axis == "x" else "VERTICAL"
    cam.angle = math.radians(float(cam_desc["fov"]))
    cam.clip_start = 1e-4
    cam.clip_end = 1e6
    obj = bpy.data.objects.new("camera", cam)
    from mathutils import Matrix
    obj.matrix_world = Matrix(rows)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj


def load(desc_path, threads):
    with open(desc_path) as f:
        desc = json.load(f)
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    setup_render(desc, threads)
    setup_camera(desc["camera"], desc["width"], desc["height"])
    mats = {name: make_material(name, spec) for name, spec in desc["materials"].items()}
    tris = 0
    for (mname, smooth), (pos, nrm) in read_obj(desc["obj"]).items():
        if mname not in mats:
            raise ValueError(f"{desc['obj']}: material {mname!r} has no description")
        tris += add_mesh(f"{mname}{'_smooth' if smooth else ''}", pos, nrm, mats[mname])
    return {"ok": True, "triangles": tris, "blender": bpy.app.version_string,
            "sampling_pattern": bpy.context.scene.cycles.sampling_pattern}


RENDER_TIME = re.compile(r"Render time \(without synchronization\):\s*([0-9.eE+-]+)")


def render(spp, seed, out):
    sc = bpy.context.scene
    sc.cycles.samples = int(spp)
    sc.cycles.seed = int(seed)
    # Cycles logs its own render time (--debug-cycles) on stderr: catch it in a file.
    log = tempfile.TemporaryFile(mode="w+b")
    sys.stderr.flush()
    saved = os.dup(2)
    os.dup2(log.fileno(), 2)
    try:
        t = time.perf_counter()
        bpy.ops.render.render(write_still=False)
        total = time.perf_counter() - t
    finally:
        sys.stderr.flush()
        os.dup2(saved, 2)
        os.close(saved)
    log.seek(0)
    text = log.read().decode(errors="replace")
    sys.stderr.write(text)  # into the driver's log
    sys.stderr.flush()
    found = RENDER_TIME.findall(text)
    bpy.data.images["Render Result"].save_render(out)
    if not found:
        return {"ok": False, "error": "Cycles did not log its render time (--debug-cycles?)",
                "total_s": total}
    return {"ok": True, "render_s": float(found[-1]), "total_s": total}


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    threads = int(argv[0]) if argv else 2
    reply({"ok": True, "blender": bpy.app.version_string, "threads": threads})
    serve({"load": lambda cmd: load(cmd["scene"], threads),
           "render": lambda cmd: render(cmd["spp"], cmd["seed"], cmd["out"])})


main()

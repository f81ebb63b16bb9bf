#!/usr/bin/env python3
"""Mitsuba 3's own values of the dielectric and plastic BSDFs at fixed local directions,
printed as C++ initialisers for tests/test_materials_dielectric.cpp and
tests/test_materials_plastic.cpp (an independent implementation as the oracle).

    /work/venv-mitsuba/bin/python scripts/mitsuba_bsdf_values.py   # Mitsuba 3.9.1, scalar_rgb

Conventions: the local frame has the normal at +z and α_u along +x (wavepath's wp_onb(+z)
is the identity); `o` is towards the viewer (Mitsuba's si.wi, wavepath's -d) and `i`
towards the light (Mitsuba's wo, wavepath's wi), each given as (θ, φ) in degrees; θ_i > 90
is a transmission. eval() is f |cos θ_i| (both programs), pdf() the density of sample().
`back` cases arrive from inside: Mitsuba gets both directions mirrored to z < 0, wavepath the
upper-side directions with front = 0. Thin dielectric: its reflectance R(θ) = the
probability that sample() reflects.
"""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")


def direction(theta_deg, phi_deg, mirror=False):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    z = math.cos(t)
    return mi.Vector3f(math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), -z if mirror else z)


def interaction(o):
    si = mi.SurfaceInteraction3f()
    si.wi = o
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    return si


def rgb(v):
    return {"type": "rgb", "value": [v, v, v]}


CTX = mi.BSDFContext()

# Direction pairs (θo, φo, θi, φi): reflections, transmissions, grazing ones.
PAIRS = [(0, 0, 0, 0), (0, 0, 30, 0), (30, 0, 30, 180), (30, 0, 45, 120), (60, 20, 50, 200),
         (75, 0, 80, 180), (45, 0, 150, 180), (0, 0, 180, 0), (30, 0, 160, 200),
         (60, 0, 130, 180), (60, 30, 110, 250), (80, 0, 120, 180), (20, 0, 95, 40)]


def dump(name, bsdf, back=False):
    print(f"// {name}{' (arriving from inside)' if back else ''}")
    for (to, po, ti, pi) in PAIRS:
        si = interaction(direction(to, po, back))
        wo = direction(ti, pi, back)
        f = bsdf.eval(CTX, si, wo)[0]
        pdf = bsdf.pdf(CTX, si, wo)
        print(f"    {{{to}, {po}, {ti}, {pi}, {f:.7g}f, {pdf:.7g}f}},")


def main():
    print(f"// Mitsuba {mi.__version__}, scalar_rgb: {{θo, φo, θi, φi, eval, pdf}}")
    rd = dict(type="roughdielectric", int_ior=1.5, ext_ior=1.0)
    dump("roughdielectric ggx α 0.3 η 1.5",
         mi.load_dict(dict(rd, distribution="ggx", alpha=0.3)))
    dump("roughdielectric ggx α 0.3 η 1.5",
         mi.load_dict(dict(rd, distribution="ggx", alpha=0.3)), back=True)
    dump("roughdielectric beckmann α 0.2 η 1.33",
         mi.load_dict(dict(type="roughdielectric", int_ior=1.33, ext_ior=1.0,
                           distribution="beckmann", alpha=0.2)))
    dump("roughdielectric ggx α_u 0.1 α_v 0.4 η 1.5, tints 0.8 / 0.6",
         mi.load_dict(dict(rd, distribution="ggx", alpha_u=0.1, alpha_v=0.4,
                           specular_reflectance=rgb(0.8), specular_transmittance=rgb(0.6))))

    print("// thindielectric η 1.5: {θ, R}")
    thin = mi.load_dict(dict(type="thindielectric", int_ior=1.5, ext_ior=1.0))
    for t in [0, 30, 60, 80, 89]:
        si = interaction(direction(t, 0))
        # R is the reflection probability: sample() reflects for sample1 <= R (bisection).
        lo, hi = 0.0, 1.0
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            bs, _ = thin.sample(CTX, si, mid, mi.Point2f(0.5, 0.5))
            if bs.wo.z > 0:
                lo = mid
            else:
                hi = mid
        print(f"    {{{t}, {lo:.7g}f}},")

    pl = dict(type="plastic", int_ior=1.5, ext_ior=1.0)
    dump("plastic η 1.5 diffuse 0.5", mi.load_dict(dict(pl, diffuse_reflectance=rgb(0.5))))
    dump("plastic η 1.9 diffuse 0.8 nonlinear",
         mi.load_dict(dict(pl, int_ior=1.9, diffuse_reflectance=rgb(0.8), nonlinear=True)))

    rp = dict(type="roughplastic", int_ior=1.5, ext_ior=1.0)
    dump("roughplastic ggx α 0.3 η 1.5 diffuse 0.5",
         mi.load_dict(dict(rp, distribution="ggx", alpha=0.3, diffuse_reflectance=rgb(0.5))))
    dump("roughplastic beckmann α 0.1 η 1.5 diffuse 0.8 nonlinear",
         mi.load_dict(dict(rp, distribution="beckmann", alpha=0.1, diffuse_reflectance=rgb(0.8),
                           nonlinear=True)))

    # The roughplastic's precomputed tables, recovered from eval() of its base alone
    # (specular_reflectance 0): eval = d / (1 - d' R) T(cos o) T(cos i) cos i / (π η²) with
    # d' = d (nonlinear) or 1, so the ratio of a nonlinear and a linear material gives R,
    # normal incidence T(1)², and T(μ) follows.
    print("// roughplastic tables (η 1.5), recovered from eval(): {distribution, α, T(μ) at "
          "μ = 0, 1/63, 32/63, 1; internal reflectance R}")
    eta = 1.5
    for dist in ["ggx", "beckmann"]:
        for alpha in [0.05, 0.3, 1.0]:
            def base(d, nonlinear):
                return mi.load_dict(dict(rp, distribution=dist, alpha=alpha, diffuse_reflectance=rgb(d),
                                         specular_reflectance=rgb(0.0), nonlinear=nonlinear))

            def ev(bsdf, mu_o, mu_i):
                si = interaction(mi.Vector3f(math.sqrt(1 - mu_o * mu_o), 0, mu_o))
                return bsdf.eval(CTX, si, mi.Vector3f(-math.sqrt(1 - mu_i * mu_i), 0, mu_i))[0]

            ratio = ev(base(0.5, True), 1, 1) / ev(base(0.5, False), 1, 1)  # (1 - R) / (1 - R / 2)
            r = (1 - ratio) / (1 - 0.5 * ratio)
            white = base(1.0, False)
            scale = (1 - r) * math.pi * eta * eta
            t1 = math.sqrt(ev(white, 1, 1) * scale)
            ts = [ev(white, 1, max(1e-6, k / 63)) * scale / max(1e-6, k / 63) / t1 for k in (0, 1, 32)]
            print(f"    {{\"{dist}\", {alpha}, {{{ts[0]:.6f}, {ts[1]:.6f}, {ts[2]:.6f}, {t1:.6f}}}, {r:.6f}}},")


if __name__ == "__main__":
    main()

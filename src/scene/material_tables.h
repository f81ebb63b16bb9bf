// material_tables.h — per-material tables that the device reads from one float buffer
// (shade.cl's material_tables, MaterialData.table), precomputed on the host.
//
// Today: the rough plastic's coat (kernels/shared/materials/roughplastic.h), as Mitsuba 3's
// roughplastic precomputes it: the external transmittance T(μ) of the rough dielectric
// interface at WP_ROUGH_PLASTIC_RES cosines μ_k = max(1e-6, k / (RES − 1)), and the
// internal diffuse reflectance R = 2 mean_k(μ_k R_in(μ_k)) (Mitsuba's own estimate of
// 2 ∫ R_in(μ) μ dμ over those same points), with R_in the reflectance of the interface seen
// from inside (relative index 1 / η). Both are single-scattering integrals over the visible
// microfacet normals h of w = (sqrt(1 − μ²), 0, μ):
//   T(μ) = ∫ D_w(h) (1 − F(w·h; η)) G(w, t) / G1(w) dh,  t = refract(w, h) below the surface,
//   R(μ) = ∫ D_w(h) F(w·h; η) G(w, r) / G1(w) dh,        r = reflect(w, h) above the surface,
// (G(w, ·) / G1(w) = G1(·) for Mitsuba's separable G), computed here in double precision by
// a product Gauss-Legendre rule in the distribution's own sampling coordinates (u ↦ θ_h with
// density D cos θ_h, azimuth φ), independent of the device's sampling code. Mitsuba instead
// runs 32² (128² inside) Gauss-Legendre nodes through its visible-normal sampler; the two
// estimates of the same integrals differ by less than 1e-3 (docs/materials.md).
// Plain host code: no OpenCL.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace wp {

// The coat of a rough plastic: its distribution (isotropic α; an anisotropic material uses
// α = sqrt(α_u α_v), the tables being for an isotropic coat as in Mitsuba, which rejects
// anisotropic rough plastics), G separable or height-correlated, η = inside / outside.
struct RoughCoat {
    double alpha = 0.1;
    double eta = 1.5;
    MicrofacetModel distribution = MicrofacetModel::GGX;
    bool separable_g = false;
    bool operator==(const RoughCoat&) const = default;
};

// The coat of material m (a RoughPlastic).
RoughCoat rough_coat(const Material& m);

// Single-scattering reflectance and transmittance (energy, no η² radiance factor) of the
// rough interface of relative index eta (η_t / η_i; < 1 seen from the denser side) for
// light arriving at cos θ = mu (0 < mu <= 1), as defined above.
double rough_interface_reflectance(const RoughCoat& c, double mu, double eta);
double rough_interface_transmittance(const RoughCoat& c, double mu, double eta);

// The WP_ROUGH_PLASTIC_TABLE_SIZE floats of a rough plastic's tables (types.h): T(μ_k) for
// k < WP_ROUGH_PLASTIC_RES, then the internal diffuse reflectance. About 0.1 s.
std::vector<float> rough_plastic_table(const RoughCoat& c);

// The material-table buffer of a scene: every material that needs tables gets them
// (identical coats share one copy) and `table[i]` is material i's offset, -1 for the others.
// Empty when no material needs any.
struct MaterialTables {
    std::vector<float> data;
    std::vector<int> table;  // per material
};
MaterialTables build_material_tables(const Scene& scene);

}  // namespace wp

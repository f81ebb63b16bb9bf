// material_kinds.h — the one list of material kinds, read by the host and the kernels.
//
// One line per kind: X(KIND, Kind, name, SPECULAR, ALPHA, IOR, ETAK)
//   KIND      the device constant WP_MATERIAL_<KIND> (= MaterialData.kind, the line's index)
//             and the compile switch WP_HAVE_<KIND> (render/kernel_config);
//   Kind      the host enumerator wp::MaterialKind::Kind (scene/scene.h);
//   name      the name in scene files, reports and to_string; the device functions
//             wp_<name>_sample / wp_<name>_eval in materials/<name>.h (see bsdf.h for
//             their contract);
//   SPECULAR  1: every event is a Dirac lobe (light sampling cannot reach it, so shade skips
//             next-event estimation; wp_material_is_specular);
//   ALPHA     1: the kind reads the microfacet roughness α (Material::alpha, ::alpha_v);
//   IOR       1: the kind reads the index of refraction (Material::ior, MaterialData.ior);
//   ETAK      1: the kind reads a conductor's complex index of refraction (Material::eta, ::k).
// Colours: MaterialData.albedo is the colour the albedo texture multiplies: the diffuse
// reflectance (diffuse, plastics), the reflection tint (mirror, glossy F0, conductors:
// specular_reflectance) or the transmittance (dielectric kinds: specular_transmittance);
// MaterialData.specular is the reflection tint of dielectrics and plastics.
// Parameters a kind does not read are uploaded as 0. Adding a kind: a line here, its
// device file materials/<name>.h, and that file's #include in bsdf.h.
// SPECULAR 0 with a Dirac part (plastic's smooth coat): sample() draws the Dirac event with
// *specular = 1 and eval() returns the non-Dirac part only. Plain macros only
// (no compat.h), so host code that knows nothing of OpenCL (scene/scene.h) may include it.
// The order is the numbering: append, never reorder (scene caches and tests store it).
#ifndef WP_MATERIAL_KINDS_H
#define WP_MATERIAL_KINDS_H

#define WP_MATERIAL_KINDS(X)                                                                   \
    X(DIFFUSE, Diffuse, diffuse, 0, 0, 0, 0) /* Lambertian, albedo */                          \
    X(MIRROR, Mirror, mirror, 1, 0, 0, 0)    /* perfect reflection, tinted by albedo */         \
    X(GLOSSY, Glossy, glossy, 0, 1, 0, 0)    /* the original program's lobe: GGX + Schlick, or Phong */ \
    X(GLASS, Glass, glass, 1, 0, 1, 0)       /* smooth dielectric, exact Fresnel */             \
    X(CONDUCTOR, Conductor, conductor, 1, 0, 0, 1) /* smooth conductor, complex Fresnel */      \
    X(ROUGH_CONDUCTOR, RoughConductor, roughconductor, 0, 1, 0, 1) /* microfacet conductor */   \
    X(ROUGH_DIELECTRIC, RoughDielectric, roughdielectric, 0, 1, 1, 0) /* Walter et al. 2007 */  \
    X(THIN_DIELECTRIC, ThinDielectric, thindielectric, 1, 0, 1, 0) /* thin slab, straight through */ \
    X(PLASTIC, Plastic, plastic, 0, 0, 1, 0) /* Mitsuba 3 plastic: smooth coat over diffuse */  \
    X(ROUGH_PLASTIC, RoughPlastic, roughplastic, 0, 1, 1, 0) /* Mitsuba 3 roughplastic */

// WP_MATERIAL_DIFFUSE = 0, ... in list order; WP_MATERIAL_KIND_COUNT kinds.
#define WP_MATERIAL_ENUM_(KIND, Kind, name, specular, alpha, ior, etak) WP_MATERIAL_##KIND,
enum { WP_MATERIAL_KINDS(WP_MATERIAL_ENUM_) WP_MATERIAL_KIND_COUNT };
#undef WP_MATERIAL_ENUM_

#endif  // WP_MATERIAL_KINDS_H


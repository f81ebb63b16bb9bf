// material_kinds.h — the one list of material kinds, read by the host and the kernels.
//
// One line per kind: X(KIND, Kind, name, SPECULAR, ALPHA, IOR)
//   KIND      the device constant WP_MATERIAL_<KIND> (= MaterialData.kind, the line's index)
//             and the compile switch WP_HAVE_<KIND> (render/kernel_config);
//   Kind      the host enumerator wp::MaterialKind::Kind (scene/scene.h);
//   name      the name in scene files, reports and to_string; the device functions
//             wp_<name>_sample / wp_<name>_eval in materials/<name>.h (see bsdf.h for
//             their contract);
//   SPECULAR  1: every event is a Dirac lobe (light sampling cannot reach it, so shade skips
//             next-event estimation; wp_material_is_specular);
//   ALPHA     1: the kind reads the GGX roughness α (Material::alpha, MaterialData.alpha);
//   IOR       1: the kind reads the index of refraction (Material::ior, MaterialData.ior).
// Parameters a kind does not read are uploaded as 0. Adding a kind: a line here, its
// device file materials/<name>.h, and that file's #include in bsdf.h. Plain macros only
// (no compat.h), so host code that knows nothing of OpenCL (scene/scene.h) may include it.
// The order is the numbering: append, never reorder (scene caches and tests store it).
#ifndef WP_MATERIAL_KINDS_H
#define WP_MATERIAL_KINDS_H

#define WP_MATERIAL_KINDS(X)                                                              \
    X(DIFFUSE, Diffuse, diffuse, 0, 0, 0) /* Lambertian, albedo */                       \
    X(MIRROR, Mirror, mirror, 1, 0, 0)    /* perfect reflection, tinted by albedo */      \
    X(GLOSSY, Glossy, glossy, 0, 1, 0)    /* GGX microfacet (or the original Phong lobe) */ \
    X(GLASS, Glass, glass, 1, 0, 1)       /* smooth dielectric, exact Fresnel */

// WP_MATERIAL_DIFFUSE = 0, ... in list order; WP_MATERIAL_KIND_COUNT kinds.
#define WP_MATERIAL_ENUM_(KIND, Kind, name, specular, alpha, ior) WP_MATERIAL_##KIND,
enum { WP_MATERIAL_KINDS(WP_MATERIAL_ENUM_) WP_MATERIAL_KIND_COUNT };
#undef WP_MATERIAL_ENUM_

#endif  // WP_MATERIAL_KINDS_H


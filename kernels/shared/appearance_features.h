// appearance_features.h — the appearance switches a stage's program is compiled with
// (KernelConfig sets them from what the scene has): shading normals, textures, normal
// maps, an environment light, anisotropic roughness. Without options they are all 0, so a
// scene without them compiles none of their code. Shared by shade.cl and aov.cl.
#ifndef WP_APPEARANCE_FEATURES_H
#define WP_APPEARANCE_FEATURES_H

#ifndef WP_HAVE_NORMALS
#define WP_HAVE_NORMALS 0
#endif
#ifndef WP_HAVE_TEXTURES
#define WP_HAVE_TEXTURES 0
#endif
#ifndef WP_HAVE_NORMAL_MAPS
#define WP_HAVE_NORMAL_MAPS 0
#endif
#ifndef WP_HAVE_ENV
#define WP_HAVE_ENV 0
#endif
#ifndef WP_HAVE_ANISOTROPY
#define WP_HAVE_ANISOTROPY 0
#endif

#endif  // WP_APPEARANCE_FEATURES_H

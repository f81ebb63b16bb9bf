// mitsuba_loader.h — Mitsuba 3 scene XML, the subset the classic research scenes use (pugixml).
//
// Reads the scene files of Bitterli's rendering resources and similar research scenes into a
// Scene: one perspective sensor, meshes and analytic shapes with their to_world transforms,
// shading normals and uvs, the common BSDFs with their textures, normal maps and masks, area,
// constant and environment-map emitters, the integrator's depth and the sample count.
//
// Parameters. `<default name="N" value="V"/>` (a child of <scene>) defines $N unless an
// override (the `params` argument, like `mitsuba -D N=V`) already did. Every attribute value
// may use `$N` (the longest run of letters, digits and '_' after '$'); a reference to an
// undefined parameter, or a '$' with no name, is an error. Parameters are read in document
// order, as Mitsuba does: a $N used before its <default> is undefined.
//
// Sensor (the first <sensor>; others are ignored with a warning):
//   perspective, or thinlens: the same with depth of field (aperture_radius, required, and
//   focus_distance [far_clip, 1e4] in world units → Camera lens_radius, focus_distance;
//   a scaling to_world, which Mitsuba 3 rejects, is warned about). to_world: its
//   column 2 is the viewing direction, column 1 up, column 0 points to the image's left (a
//   matrix whose column 0 points right would mirror the image: warning, rendered unmirrored).
//   fov with fov_axis x (Mitsuba's default), y, smaller, larger or diagonal, or
//   focal_length "Nmm" (36 x 24 mm film, diagonal fov) → wavepath's vertical fov.
//   film width/height (defaults 768 x 576) → camera size; sampler sample_count → render.spp,
//   seed → render.seed. near_clip/far_clip are accepted and ignored; a reconstruction filter
//   other than box is ignored with a warning (wavepath box-filters each pixel).
//   No sensor: the camera frames the scene's bounding box from +z (800 x 600, 40° vertical).
// Integrator: max_depth N (Mitsuba: N path segments) → render.depth = N − 1 bounces.
//   max_depth −1 (unbounded, also Mitsuba's default when the integrator or max_depth is
//   absent) → 64 bounces; Russian roulette ends almost every path long before that, so
//   the cost is that of the paths that matter. max_depth > 65 is capped at 64 bounces (warning),
//   max_depth 0 (Mitsuba renders black) → depth 0 (warning). Types other than path, volpath,
//   volpathmis: warning (wavepath's path tracer renders them).
// Shapes (to_world = matrix, translate, rotate, scale, lookat, composed in document order:
//   each new one is applied after the previous ones, M = new · M):
//   obj, ply      `filename` relative to the XML file's folder, through load_mesh_file (the
//                 mesh file's own materials are ignored, as Mitsuba does; flip_normals honoured).
//                 The file's vertex normals shade; where it has none, smooth vertex normals
//                 are computed (scene/normals.h, no crease), as Mitsuba does, unless
//                 face_normals is true (then the file's normals are dropped too). Its uvs are
//                 kept (the loaders store 1 − v, Mitsuba's default flip_tex_coords = true;
//                 flip_tex_coords = false undoes it)
//   rectangle     [−1, 1]² in the z = 0 plane, normal +z (2 triangles), uv ((x + 1)/2, (y + 1)/2)
//   cube          [−1, 1]³, normals outward: Mitsuba's 24-vertex mesh (12 triangles), each face
//                 the whole texture with Mitsuba's uvs
//   sphere        center, radius (then to_world): an icosphere of 5,120 triangles whose radius
//                 is scaled so that its area is 4πr² (an emitter keeps its power); normals
//                 (p − c)/|p − c|; uv (φ/2π, θ/π), φ = atan2(y, x) in [0, 2π), θ from +z, in
//                 the sphere's own space (vertices at the seam and the poles are split)
//   disk          radius 1 in z = 0, normal +z: 128 segments, area π; uv (r, φ/2π)
//   cylinder      p0, p1, radius (open tube, normals outward): 128 segments, area 2πrh, in
//                 Mitsuba's frame (coordinate_system of p1 − p0); normals radial; uv (φ/2π, z)
//   Flat shapes carry no normals (the geometric one shades); uvs are kept only for shapes
//   whose material has a texture, so untextured scenes carry none. A mirroring to_world or
//   flip_normals reverses the winding and turns the normals with it (inverse transpose).
//   Other shape types (serialized, shapegroup, instance, ...) are skipped with a warning.
//   A shape without a BSDF gets Mitsuba's default, diffuse 0.5.
// BSDFs (by nesting or <ref id>; wavepath materials shade both sides). The rough kinds take
//   Mitsuba's microfacet model exactly: `distribution` beckmann (the default) or ggx, the
//   separable masking G1(wo)·G1(wi) (Material::separable_g), visible-normal sampling
//   (sample_visible is accepted; it changes the noise only); α < 1e-4 → the smooth kind
//   (warning), α > 2 → 2 (warning):
//   twosided(X)             X (a second, back-side BSDF is dropped with a warning)
//   diffuse                 Diffuse, albedo = reflectance (default 0.5)
//   conductor               Conductor: η, k per channel from eta/k (defaults 0 and 1), or
//                           from `material` in the metal table below (default "none": η 0,
//                           k 1, F = 1; an unknown name: warning and "none"); albedo =
//                           specular_reflectance (default 1), which scales the exact Fresnel
//   roughconductor          RoughConductor, same η/k/albedo; alpha (default 0.1; a texture:
//                           see Textures) or alpha_u + alpha_v (anisotropic: Material::alpha =
//                           α_u along the shading frame's x = wp_onb(n), Mitsuba's frame on
//                           shapes without uvs; alpha_v)
//   dielectric              Glass, ior = int_ior / ext_ior (numbers or names: vacuum,
//                           helium, hydrogen, air, carbon dioxide, water, acetone, ethanol,
//                           carbon tetrachloride, glycerol, benzene, silicone oil, bromine,
//                           water ice, fused quartz, pyrex, acrylic glass, polypropylene,
//                           bk7, sodium chloride, amber, pet, diamond; defaults bk7 / air;
//                           or `eta`), albedo = specular_transmittance, specular =
//                           specular_reflectance (both default 1)
//   roughdielectric         RoughDielectric, the same plus the roughness (as roughconductor)
//   thindielectric          ThinDielectric, the same parameters as dielectric
//   plastic                 Plastic: albedo = diffuse_reflectance (default 0.5), specular =
//                           specular_reflectance (default 1), ior = int_ior / ext_ior
//                           (defaults polypropylene / air), nonlinear
//   roughplastic            RoughPlastic, the same plus distribution and alpha (a number
//                           only; alpha_u/alpha_v and an alpha texture are errors, as in
//                           Mitsuba 3)
//   principled, principledthin → Diffuse with base_color (warning)
//   normalmap               its nested BSDF with the `normalmap` texture as its tangent-space
//                           normal map (normal_scale 1) in Mitsuba's frame: x along dp/du,
//                           y = n × x whatever the handedness of the uvs (the shapes get
//                           tangents dp/du with w = +1: per vertex, the mean of its faces'
//                           dp/du, where Mitsuba's meshes use each face's); a missing file
//                           leaves the BSDF unchanged
//   mask                    its nested BSDF with an alpha cut-out: coverage = the `opacity`
//                           (default 0.5; a texture's luminance) in the A channel of an alpha
//                           map made from it, cutoff 0.5. Mitsuba's mask is stochastic, so this
//                           is exact only for opacity 0 or 1: anything else warns once. A
//                           missing opacity file leaves the surface opaque
//   blendbsdf, bumpmap → their first nested BSDF (warning)
//   null → black Diffuse (warning); anything else → Diffuse 0.5 (warning)
//   A reflecting BSDF that is not inside twosided is one-sided in Mitsuba (black from
//   behind); wavepath shades it on both sides: one warning.
// Textures (inline <texture name=...> or <ref name=... id=...> to a top-level one), wherever a
//   BSDF takes a reflectance (diffuse reflectance, conductor specular_reflectance, plastic
//   diffuse_reflectance, principled base_color, dielectric specular_transmittance → the
//   albedo map, the constant 1), roughconductor and roughdielectric alpha, normalmap, mask
//   opacity and an area emitter's radiance (→ emission map, emission 1):
//   bitmap        filename (relative to the XML file; missing: a warning and a placeholder,
//                 scene/texture.h), raw (true: data, else an sRGB-encoded colour),
//                 filter_type bilinear | nearest (→ Texture::nearest, for every use of that
//                 file), wrap_mode repeat (mirror, clamp: rendered as repeat, warning), to_uv
//                 (its x/y rows and columns and translation → TextureRef::uv_transform),
//                 format and accel ignored
//   checkerboard  color0 (0.4), color1 (0.2), to_uv: a 2 x 2 nearest image (color0 top left)
//   Other texture types: 0.5 grey (warning). alpha as a texture: alpha_max × G² with
//   G = sqrt(a / alpha_max) per texel (a: the texel's luminance, Mitsuba's eval_1);
//   alpha_u/alpha_v as textures: their mean values (warning). A texture where wavepath takes
//   a constant (eta, k, a dielectric's or plastic's specular_reflectance, a constant
//   emitter's radiance, ...): its mean (checkerboard) or 0.5, with a warning.
//   Metals (scene/metals.h: RGB η, k fitted by Tungsten's ComplexIorData.hpp from the spectral
//   data Mitsuba uses; Mitsuba 3.9.1's own scalar_rgb values of Ag, Al, Au, Cr, Cu differ by
//   < 2e-3): Ag, Al, Au, Be, Cr, Cu, Hg, Ir, K, Li, MgO, Mo, Rh, Ta, TiN, TiO2, VN, W,
//   Na_palik, Ni_palik.
// Emitters: area (inside a shape): radiance → emission of a material made for that shape
//   (front side = the shape's normal side). constant (top level): radiance → background
//   (several add up). envmap (top level): filename (as a bitmap's, read as colour), scale
//   (default 1, >= 0), to_world (its rotation; a scale or shear is dropped with a warning) →
//   Scene::environment; filter_type and mis_compensation are ignored; a second envmap is an
//   error. Others (point, spot, directional, ...) are skipped (warning).
// Colours: <rgb value="r, g, b"> or one value, <spectrum value="v"> (or "λ:v, ..." pairs:
//   their mean, warning), <float>. Reflectances must lie in [0, 1], radiances be >= 0.
//
// Warnings: every element, property or value that is not represented exactly gets a warning
// naming file:line:column, aggregated: one line per kind ("... (5 times; the first here)").
// Errors (wp::Error, one message "FILE:LINE:COL: <element ...>: problem"): malformed XML
// (pugixml's message at its line:column), an element that is not part of Mitsuba's format
// (known but unsupported ones such as <include>, <medium> only warn), an attribute the
// element does not take, a missing required attribute, an undefined $parameter, a value
// that is not a number or out of range (fov outside (0, 180), film size outside
// [1, 16384] or over 2^28 pixels, sample_count outside [1, 2^24] (util/limits.h), negative
// radius, ...), a <ref> to an undefined id, a duplicate id, a mesh file that is missing or
// fails to load, more than 2^25 triangles in all, BSDF nesting deeper than 16, element
// nesting deeper than 64, an attribute that expands to over 64 KiB, int_ior / ext_ior
// outside [0.01, 100], a bitmap without a filename or with an unknown filter_type or
// wrap_mode, a checkerboard reflectance outside [0, 1], a normalmap without its texture, a
// second envmap (naming the first).
// Nothing is printed; the result has passed validate_scene.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace wp {

// $parameters set from outside the file (as Mitsuba's -D NAME=VALUE); they win over <default>.
using MitsubaParams = std::map<std::string, std::string>;

// Reads the file and parses it; relative mesh paths resolve against the file's folder.
Scene load_mitsuba(const std::filesystem::path& path);
Scene load_mitsuba(const std::filesystem::path& path, const MitsubaParams& params);

// Parses XML held in memory. `origin` names the file in messages and its folder is where
// relative filenames resolve. Never writes files; returns a Scene or throws wp::Error.
Scene parse_mitsuba(std::string_view xml, const std::filesystem::path& origin);
Scene parse_mitsuba(std::string_view xml, const std::filesystem::path& origin,
                    const MitsubaParams& params);

} // namespace wp

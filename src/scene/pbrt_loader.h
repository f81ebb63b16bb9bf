// pbrt_loader.h — pbrt-v4 scene files, the subset that Bitterli's pbrt-v4 scenes and
// pbrt-v4's own test scenes use. The full mapping, with what is approximated and how, is
// docs/pbrt.md; in short:
//
// Syntax: pbrt-v4's tokens (quoted strings with \-escapes, numbers, [ ], # comments), every
// directive of pbrt-v4's grammar (an unknown word is an error), parameter lists
// "TYPE NAME" VALUE | [ VALUES ] with the types integer, float, point2, vector2, point3,
// vector3, normal3 (normal), rgb (color), spectrum, blackbody, bool, string, texture
// (pbrt-v3's point, vector, color accepted as pbrt-v4 upgrades them).
// Include "file" and Import "file" (relative paths resolve against the top-level file's
// folder, as pbrt-v4's search directory does); Import keeps the graphics state of the
// importing file. Cycles, nesting and the number of files are bounded (util/limits.h).
// Transforms: Identity, Translate, Scale, Rotate, LookAt, Transform, ConcatTransform
// (16 numbers, column by column as pbrt writes them), CoordinateSystem, CoordSysTransform
// ("camera" and "world" predefined), ActiveTransform (only the start time's transform is
// used). Graphics state: AttributeBegin/End, pbrt-v3's TransformBegin/End (push and pop the
// transform), ReverseOrientation, Attribute (defaults for shapes, lights, materials, ...).
// WorldBegin resets the transform; the camera's transform is the inverse of the transform
// at Camera.
// Shapes: trianglemesh, plymesh (through load_mesh_file), bilinearmesh (each patch two
// triangles), sphere (an icosphere of 5,120 triangles with area 4πr²), disk (annulus,
// 128 segments), loopsubdiv (its control mesh); ObjectBegin/End/ObjectInstance flattened.
// Camera "perspective" (fov on the shorter image axis, screenwindow, frameaspectratio,
// lensradius / focaldistance), Film xresolution / yresolution, Sampler pixelsamples → spp,
// Integrator maxdepth → depth (both count bounces). Materials diffuse, conductor,
// dielectric, thindielectric, coateddiffuse, and the nearest kind for the others;
// Texture imagemap, checkerboard, constant, scale, mix; AreaLightSource "diffuse";
// LightSource "infinite" (L, or a filename: pbrt-v4's equal-area square map, resampled to
// wavepath's equirectangular map).
//
// Anything represented inexactly gets one warning per kind ("FILE:LINE:COL: ... (N times;
// the first here)") in Scene::warnings. Errors are wp::Error "FILE:LINE:COL: problem" (the
// included file's name where it happened); nothing is printed. The result has passed
// validate_scene.
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

// Reads the file and parses it.
Scene load_pbrt(const std::filesystem::path& path);

// Parses pbrt text held in memory. `origin` names it in messages; its folder is where
// relative file names (Include, Import, plymesh, textures, environment maps) resolve.
// Never writes files; returns a Scene or throws wp::Error.
Scene parse_pbrt(std::string_view text, const std::filesystem::path& origin);

}  // namespace wp

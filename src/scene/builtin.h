// builtin.h — the scenes that live in the binary: wavepath's Cornell box and the closed
// "furnace" box of the analytic end-to-end test.
//
// Cornell box layout (y up, right-handed, units as in Bitterli's box):
//   * walls: x in [-1, 1], y in [0, 2], z in [-1, 1], open at z = +1 towards the camera;
//     red left wall (x = -1), green right wall (x = +1), white floor, ceiling and back
//     wall (z = -1); all Lambertian, every wall a single quad (2 triangles) facing inward;
//   * light: the quad x in [-0.24, 0.23], z in [-0.22, 0.16] at y = 1.98 (2 cm under the
//     ceiling), emitting (17, 12, 4) downward only (Bitterli's light);
//   * mirror: a UV sphere of radius 0.4 resting on the floor at front right, centre
//     (0.42, 0.401, 0.3);
//   * glossy: a tall box 0.6 x 1.2 x 0.6 (Phong exponent 100, white albedo) at back left,
//     turned 17 degrees about y, centre of its base (-0.33, 0, -0.32);
//   * camera: (0, 1, 3.9) looking at (0, 1, 0), vertical fov 40 degrees, 800 x 600, so the
//     front opening fills the frame height; background black.
// The two objects share object_triangles (about a quarter to the box, the rest to the
// sphere, whose rings x segments are chosen to land close to the budget); walls and light
// add 12. The default gives 16,020 triangles: walls 10, light 2, glossy box 3,888 (18 x 18
// cells per face), mirror sphere 12,120 (61 rings x 101 segments). The original student
// program rendered 16,024.
#pragma once

#include "scene/scene.h"

namespace wp {

// wavepath's built-in scene, named "cornell-box" (see the layout above).
Scene make_cornell_box(int object_triangles = 16000);

// A closed cube [-1, 1]^3 seen from inside: every wall Lambertian with albedo `albedo` and
// emitting radiance `emission` (grey) towards the inside. With unbounded path depth every
// pixel converges to emission / (1 - albedo); after D bounces, to
// emission * (1 + albedo + ... + albedo^D). Walls are 4 x 4 grids (192 triangles, shared
// vertices); the camera sits inside at (0.1, -0.05, 0.2) looking at the corner (-1, -1, -1),
// 64 x 48 film, 40 degrees vertical fov. Named "closed-box-furnace".
Scene make_closed_box_furnace(float emission, float albedo);

// The multiple-importance-sampling scene in the spirit of Veach's (Veach & Guibas 1995,
// figure 5; Veach 1997, figure 9.2), named "veach-plates": four glossy plates (GGX
// roughness α = 0.30, 0.15, 0.07, 0.02 from front to back, stored as given; albedo / F0
// 0.7) tilted so that each mirrors the point (0, 3, −3) towards the camera, and four
// spherical lights of radius 0.03, 0.1, 0.3, 0.9 at y = 3, z = −3,
// x = −2.25 … 2.25, with radiance ∝ 1 / r² (equal power: a small bright light … a large dim
// light); a dark diffuse floor (albedo 0.2) at y = −0.6; black background. Camera (0, 2, 7)
// looking at (0, 0.6, 0), 35 degrees vertical fov, 768 x 512.
Scene make_veach_plates();

} // namespace wp

// light_pairs.h — back-to-back pairs of light triangles, so that light sampling draws the
// half of a closed emitter that faces the receiver (kernels/shared/lights.h).
//
// Next-event estimation picks a light triangle by power and a uniform point on it; from a
// receiver outside a closed emitter (a tessellated sphere light) about half of those points
// lie on triangles that face away, and their samples are wasted. Each light triangle t gets
// a partner t' on the far side of its emitter, mutually (t' pairs with t). A sample whose
// triangle faces away from the receiver while its partner faces it moves to the partner,
// at the same barycentric coordinates: a uniform point on t' (the map between the two
// triangles' uniform distributions is one-to-one). Its density per unit area on t' is then
// P(t') / A(t') + P(t) / A(t'), which the kernels evaluate from the same facing test at
// both ends of MIS (the light sample and a BSDF-sampled hit on t'). The estimate stays
// unbiased for any pairing; the pairing only decides how much variance it removes (about
// half of a sphere light's samples came back black).
//
// Pairs: light triangles connected through shared vertex positions form one emitter. Two
// triangles of an emitter that face opposite ways (normals with a negative dot product) are
// candidates when each centroid lies near the reflection of the other through the emitter's
// centre (its area-weighted centroid); candidates are matched greedily, the closest to exact
// reflections first. A centrally symmetric mesh (icospheres, boxes) pairs every triangle
// with its antipode, a UV sphere nearly every one; a flat emitter (a quad light) none.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace wp {

// Triangle i as a light of next-event estimation: its area and power (area times the
// emission's luminance), both 0 unless it is one — emissive, positive area and luminance,
// finite power (build_light_table's rule and weights, scene/upload.h).
struct LightTriangle {
    double area = 0.0;
    double power = 0.0;
};
LightTriangle light_triangle(const Scene& scene, std::size_t i);
inline bool is_light_triangle(const Scene& scene, std::size_t i) { return light_triangle(scene, i).power > 0.0; }

// partner[i] for every triangle of the scene (scene order): the light triangle paired with
// light triangle i, or -1 (no partner, or i is no light). Mutual: partner[partner[i]] == i.
std::vector<int> find_light_partners(const Scene& scene);

}  // namespace wp

#include "scene/normals.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <tuple>

#include "util/error.h"

namespace wp {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Bits of a float for exact-equality keys, with -0 folded onto +0.
std::uint32_t key_bits(float f) { return std::bit_cast<std::uint32_t>(f == 0.0f ? 0.0f : f); }

bool is_zero(const glm::vec3& v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The angle between a and b in [0, pi], accurate for small and large angles alike.
double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Disjoint sets over corner ids; the smaller id is the root, so results do not depend on
// the order of the unions.
struct UnionFind {
    std::vector<std::uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) {
        for (std::size_t i = 0; i < n; ++i) parent[i] = std::uint32_t(i);
    }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];  // path halving
            x = parent[x];
        }
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        if (a < b) std::swap(a, b);
        parent[a] = b;
    }
};

// Faces sharing one edge beyond this many (a non-manifold fan) are compared only with their
// neighbour in edge order, not with every other one, so a pathological edge stays linear.
constexpr std::size_t kMaxEdgeFanPairs = 32;

void check_indices(const Scene& s, const char* who) {
    const std::size_t nv = s.positions.size();
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            if (s.triangles[t][k] >= nv)
                fail("{}: triangle {} uses vertex {}, but the scene has {} positions", who, t,
                     s.triangles[t][k], nv);
    auto sized = [&](std::size_t n, const char* what) {
        if (n != 0 && n != nv)
            fail("{}: the scene has {} {} for {} positions", who, n, what, nv);
    };
    sized(s.normals.size(), "normals");
    sized(s.uvs.size(), "uvs");
    sized(s.tangents.size(), "tangents");
}

// Items 0..n-1 grouped by bucket(i) < buckets (a counting sort, stable): the items of
// bucket b are order[start[b]] .. order[start[b + 1] - 1], in increasing index.
struct Buckets {
    std::vector<std::uint32_t> order, start;
};
template <class F>
Buckets bucket_by(std::size_t n, std::size_t buckets, F bucket) {
    Buckets r;
    r.start.assign(buckets + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++r.start[bucket(i) + 1];
    for (std::size_t b = 0; b < buckets; ++b) r.start[b + 1] += r.start[b];
    r.order.resize(n);
    std::vector<std::uint32_t> next(r.start.begin(), r.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) r.order[next[bucket(i)]++] = std::uint32_t(i);
    return r;
}

// A unit vector orthogonal to the unit vector n (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited").
glm::dvec3 any_orthogonal(const glm::dvec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    return {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

}  // namespace

void smooth_normals(Scene& s, float crease_deg, std::size_t first) {
    if (!(crease_deg >= 0.0f))
        fail("smooth_normals: crease angle {} degrees: need a number >= 0", crease_deg);
    const std::size_t nt = s.triangles.size();
    if (first >= nt) return;
    check_indices(s, "smooth_normals");  // all triangles: those before `first` are read too
    const std::size_t nv = s.positions.size();
    const bool had_normals = !s.normals.empty();

    // The set: triangles of the range without shading normals; `shared` marks vertices
    // that triangles outside the set use too (their normals must not change).
    std::vector<std::uint32_t> faces;
    std::vector<char> shared(nv, 0);
    for (std::size_t t = 0; t < nt; ++t) {
        const glm::uvec3& tri = s.triangles[t];
        const bool none = !had_normals || (is_zero(s.normals[tri.x]) &&
                                           is_zero(s.normals[tri.y]) && is_zero(s.normals[tri.z]));
        if (t >= first && none)
            faces.push_back(std::uint32_t(t));
        else
            shared[tri.x] = shared[tri.y] = shared[tri.z] = 1;
    }
    if (faces.empty()) return;
    const std::size_t nf = faces.size(), nc = 3 * nf;
    if (nc > kNone) fail("smooth_normals: {} triangles are too many", nf);
    auto vert = [&](std::size_t c) { return s.triangles[faces[c / 3]][int(c % 3)]; };

    // 1. Unit face normals and the angle of each corner, in double. A face with a zero
    //    cross product (exactly collinear float vertices give exactly zero: differences and
    //    products of floats are exact in double) or a non-finite one is degenerate.
    std::vector<glm::dvec3> fn(nf);
    std::vector<char> good(nf, 0);
    std::vector<double> angle(nc, 0.0);
    for (std::size_t f = 0; f < nf; ++f) {
        const glm::uvec3& tri = s.triangles[faces[f]];
        const glm::dvec3 p[3] = {glm::dvec3(s.positions[tri.x]), glm::dvec3(s.positions[tri.y]),
                                 glm::dvec3(s.positions[tri.z])};
        const glm::dvec3 e = glm::cross(p[1] - p[0], p[2] - p[0]);
        const double len = glm::length(e);
        if (!(len > 0.0) || !std::isfinite(len) || !finite(p[0]) || !finite(p[1]) ||
            !finite(p[2]))
            continue;
        good[f] = 1;
        fn[f] = e / len;
        for (int k = 0; k < 3; ++k)
            angle[3 * f + k] = angle_between(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
    }

    // 2. Position ids: vertices with bit-identical positions are one point for adjacency.
    std::vector<std::uint32_t> pid(nv, kNone);
    {
        std::vector<std::uint32_t> used;
        std::vector<char> seen(nv, 0);
        for (std::size_t c = 0; c < nc; ++c)
            if (!seen[vert(c)]) {
                seen[vert(c)] = 1;
                used.push_back(vert(c));
            }
        using Key = std::array<std::uint32_t, 4>;  // position bits, then the index
        std::vector<Key> keys(used.size());
        for (std::size_t i = 0; i < used.size(); ++i) {
            const glm::vec3& p = s.positions[used[i]];
            keys[i] = {key_bits(p.x), key_bits(p.y), key_bits(p.z), used[i]};
        }
        std::sort(keys.begin(), keys.end());
        std::uint32_t id = 0;
        for (std::size_t i = 0; i < keys.size(); ++i) {
            if (i > 0 && !std::equal(keys[i].begin(), keys[i].begin() + 3, keys[i - 1].begin()))
                ++id;
            pid[keys[i][3]] = id;
        }
    }

    // 3. Smoothing groups: corners at one point joined across shared edges whose faces'
    //    normals differ by at most the crease angle (union-find over corners).
    UnionFind groups(nc);
    const bool smooth_all = crease_deg >= 180.0f;
    // Tolerance: coplanar faces' normals differ by rounding (~1e-16), so crease 0 joins them.
    const double min_cos =
        smooth_all ? -2.0 : std::cos(double(crease_deg) * std::numbers::pi / 180.0) - 1e-9;
    {
        struct Edge {
            std::uint64_t ends;        // position ids lo < hi, as lo << 32 | hi
            std::uint32_t c_lo, c_hi;  // the face's corners at lo and at hi
        };
        auto edge = [](std::uint64_t lo, std::uint64_t hi, std::uint32_t c_lo, std::uint32_t c_hi) {
            return Edge{lo << 32 | hi, c_lo, c_hi};
        };
        std::vector<Edge> edges;
        edges.reserve(nc);
        for (std::size_t f = 0; f < nf; ++f) {
            if (!good[f]) continue;
            for (int k = 0; k < 3; ++k) {
                auto ca = std::uint32_t(3 * f + k), cb = std::uint32_t(3 * f + (k + 1) % 3);
                std::uint32_t a = pid[vert(ca)], b = pid[vert(cb)];
                if (a == b) continue;  // cannot happen for a good face; kept for safety
                edges.push_back(a < b ? edge(a, b, ca, cb) : edge(b, a, cb, ca));
            }
        }
        std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
            return x.ends < y.ends || (x.ends == y.ends && x.c_lo < y.c_lo);
        });
        for (std::size_t i = 0; i < edges.size();) {
            std::size_t j = i + 1;
            while (j < edges.size() && edges[j].ends == edges[i].ends) ++j;
            const bool all_pairs = j - i <= kMaxEdgeFanPairs;
            for (std::size_t x = i; x < j; ++x)
                for (std::size_t y = x + 1; y < (all_pairs ? j : std::min(j, x + 2)); ++y) {
                    const Edge &ex = edges[x], &ey = edges[y];
                    if (glm::dot(fn[ex.c_lo / 3], fn[ey.c_lo / 3]) >= min_cos) {
                        groups.unite(ex.c_lo, ey.c_lo);
                        groups.unite(ex.c_hi, ey.c_hi);
                    }
                }
            i = j;
        }
    }
    if (smooth_all) {
        // Every face at a vertex index smooths with the others there (Mitsuba's rule), even
        // when they share no edge.
        std::vector<std::uint32_t> first_corner(nv, kNone);
        for (std::size_t c = 0; c < nc; ++c) {
            if (!good[c / 3]) continue;
            std::uint32_t& fc = first_corner[vert(c)];
            if (fc == kNone)
                fc = std::uint32_t(c);
            else
                groups.unite(fc, std::uint32_t(c));
        }
    }

    // 4. Each group's normal: the angle-weighted sum of its faces' unit normals (Thürmer &
    //    Wüthrich 1998), zero where they cancel (relative to the total weight).
    std::vector<glm::vec3> corner_normal(nc, glm::vec3(0.0f));
    bool any_normal = false;
    {
        std::vector<glm::dvec3> sum(nc, glm::dvec3(0.0));
        std::vector<double> weight(nc, 0.0);
        for (std::size_t c = 0; c < nc; ++c) {
            if (!good[c / 3]) continue;
            const std::uint32_t r = groups.find(std::uint32_t(c));
            sum[r] += angle[c] * fn[c / 3];
            weight[r] += angle[c];
        }
        for (std::size_t c = 0; c < nc; ++c) {
            if (!good[c / 3]) continue;
            const std::uint32_t r = groups.find(std::uint32_t(c));
            const double len = glm::length(sum[r]);
            if (len > 1e-6 * weight[r]) {
                corner_normal[c] = glm::vec3(sum[r] / len);
                any_normal = true;
            }
        }
    }
    if (!any_normal && !had_normals) return;  // nothing to smooth: leave the scene as it was

    // 5. One output vertex per (vertex index, distinct normal). Corners grouped by vertex,
    //    then sorted good ones first and by normal, so equal normals are adjacent.
    std::vector<std::array<std::uint32_t, 4>> keys(nc);
    for (std::size_t c = 0; c < nc; ++c) {
        const glm::vec3& n = corner_normal[c];
        keys[c] = {good[c / 3] ? 0u : 1u, key_bits(n.x), key_bits(n.y), key_bits(n.z)};
    }
    Buckets by_vertex = bucket_by(nc, nv, [&](std::size_t c) { return vert(c); });
    std::vector<std::uint32_t>& order = by_vertex.order;
    for (std::size_t v = 0; v < nv; ++v)
        std::sort(order.begin() + by_vertex.start[v], order.begin() + by_vertex.start[v + 1],
                  [&](std::uint32_t a, std::uint32_t b) {
                      return std::tie(keys[a], a) < std::tie(keys[b], b);
                  });

    if (!had_normals) s.normals.assign(nv, glm::vec3(0.0f));
    std::vector<std::uint32_t> out(nc, kNone);
    auto new_vertex = [&](std::uint32_t v, const glm::vec3& n) {
        if (s.positions.size() >= kNone) fail("smooth_normals: too many vertices after splitting");
        const glm::vec3 p = s.positions[v];
        s.positions.push_back(p);
        s.normals.push_back(n);
        if (!s.uvs.empty()) {
            const glm::vec2 uv = s.uvs[v];
            s.uvs.push_back(uv);
        }
        if (!s.tangents.empty()) {
            const glm::vec4 t = s.tangents[v];
            s.tangents.push_back(t);
        }
        return std::uint32_t(s.positions.size() - 1);
    };
    for (std::size_t i = 0; i < nc;) {
        const std::uint32_t v = vert(order[i]);
        std::size_t j = i;
        while (j < nc && vert(order[j]) == v) ++j;
        // Runs of equal normals among the good corners [i, g); degenerate ones [g, j).
        std::size_t g = i;
        while (g < j && good[order[g] / 3]) ++g;
        bool v_taken = false;  // v itself has been given to a run
        auto place = [&](const glm::vec3& n) {
            // A vertex only the set uses keeps its index for its first run; a shared one
            // keeps it only for a zero normal (what it has already).
            if (!v_taken && (!shared[v] || is_zero(n))) {
                v_taken = true;
                s.normals[v] = n;
                return v;
            }
            return new_vertex(v, n);
        };
        std::uint32_t first_run = kNone;
        for (std::size_t a = i; a < g;) {
            std::size_t b = a + 1;
            const glm::vec3 n = corner_normal[order[a]];
            while (b < g && keys[order[b]] == keys[order[a]]) ++b;
            const std::uint32_t idx = place(n);
            if (first_run == kNone) first_run = idx;
            for (std::size_t k = a; k < b; ++k) out[order[k]] = idx;
            a = b;
        }
        if (g < j) {
            // Degenerate faces take the first group's vertex, or a flat one of their own.
            const std::uint32_t idx = first_run != kNone ? first_run : place(glm::vec3(0.0f));
            for (std::size_t k = g; k < j; ++k) out[order[k]] = idx;
        }
        i = j;
    }
    for (std::size_t c = 0; c < nc; ++c) s.triangles[faces[c / 3]][int(c % 3)] = out[c];
}

std::vector<glm::vec4> corner_tangents(const Scene& s) {
    const std::size_t nt = s.triangles.size();
    std::vector<glm::vec4> out(3 * nt, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    if (nt == 0) return out;
    check_indices(s, "corner_tangents");
    const std::size_t nc = 3 * nt;
    if (nc > kNone) fail("corner_tangents: {} triangles are too many", nt);
    const bool has_n = !s.normals.empty(), has_uv = !s.uvs.empty(), has_t = !s.tangents.empty();
    auto vert = [&](std::size_t c) { return s.triangles[c / 3][int(c % 3)]; };

    // 1. Per face: the corners' normals, the unit tangent direction dP/du with the sign of
    //    the uv area, and whether the face is usable (mikktspace.c InitTriInfo). uvs are
    //    taken v-up, (u, -v), so that sign gives w with b = w cross(n, t) towards the
    //    image's top.
    std::vector<glm::dvec3> n(nc);
    std::vector<glm::dvec3> ft(nt, glm::dvec3(0.0));
    std::vector<signed char> sign(nt, 0);  // +1 / -1 for a usable face, 0 otherwise
    for (std::size_t f = 0; f < nt; ++f) {
        const glm::uvec3& tri = s.triangles[f];
        const glm::dvec3 p0(s.positions[tri.x]), p1(s.positions[tri.y]), p2(s.positions[tri.z]);
        const glm::dvec3 d1 = p1 - p0, d2 = p2 - p0;
        const glm::dvec3 ng = glm::cross(d1, d2);
        const double glen = glm::length(ng);
        const bool pos_ok = glen > 0.0 && std::isfinite(glen);
        bool smooth = has_n;
        for (int k = 0; k < 3 && smooth; ++k) {
            const glm::dvec3 sn(s.normals[tri[k]]);
            smooth = !is_zero(s.normals[tri[k]]) && finite(sn) && std::isfinite(glm::length(sn));
        }
        for (int k = 0; k < 3; ++k) {
            if (smooth)
                n[3 * f + k] = glm::normalize(glm::dvec3(s.normals[tri[k]]));
            else
                n[3 * f + k] = pos_ok ? ng / glen : glm::dvec3(0.0, 0.0, 1.0);
        }
        if (!pos_ok || !has_uv) continue;
        const glm::dvec2 w0(s.uvs[tri.x].x, -double(s.uvs[tri.x].y));
        const glm::dvec2 w1(s.uvs[tri.y].x, -double(s.uvs[tri.y].y));
        const glm::dvec2 w2(s.uvs[tri.z].x, -double(s.uvs[tri.z].y));
        const glm::dvec2 t1 = w1 - w0, t2 = w2 - w0;
        const double area = t1.x * t2.y - t2.x * t1.y;  // twice the signed uv area
        const glm::dvec3 os = t2.y * d1 - t1.y * d2;    // area * dP/du
        const double olen = glm::length(os);
        if (area == 0.0 || !std::isfinite(area) || !(olen > 0.0) || !std::isfinite(olen)) continue;
        sign[f] = area > 0.0 ? 1 : -1;
        ft[f] = (double(sign[f]) / olen) * os;
    }

    // 2. Vertices as mikktspace.c identifies them: equal position, normal and uv (the
    //    normal as the corner uses it). First vertex indices with equal position and uv get
    //    one id (a sort of the vertices), then each id's corners are sorted by normal and
    //    sign, so corners of one vertex are adjacent in `order`.
    std::vector<std::uint32_t> same_id(s.positions.size());
    std::size_t ids = 0;
    {
        using VKey = std::array<std::uint32_t, 6>;  // position and uv bits, then the index
        std::vector<VKey> vkeys(s.positions.size());
        for (std::size_t v = 0; v < vkeys.size(); ++v) {
            const glm::vec3& p = s.positions[v];
            const glm::vec2 uv = has_uv ? s.uvs[v] : glm::vec2(0.0f);
            vkeys[v] = {key_bits(p.x),  key_bits(p.y),  key_bits(p.z),
                        key_bits(uv.x), key_bits(uv.y), std::uint32_t(v)};
        }
        std::sort(vkeys.begin(), vkeys.end());
        for (std::size_t i = 0; i < vkeys.size(); ++i) {
            if (i > 0 && !std::equal(vkeys[i].begin(), vkeys[i].begin() + 5, vkeys[i - 1].begin()))
                ++ids;
            same_id[vkeys[i][5]] = std::uint32_t(ids);
        }
        ++ids;
    }
    using Key = std::array<std::uint32_t, 4>;  // normal bits, sign + 1
    std::vector<Key> keys(nc);
    for (std::size_t c = 0; c < nc; ++c) {
        const glm::vec3 nf(n[c]);
        keys[c] = {key_bits(nf.x), key_bits(nf.y), key_bits(nf.z), std::uint32_t(sign[c / 3] + 1)};
    }
    Buckets by_id = bucket_by(nc, ids, [&](std::size_t c) { return same_id[vert(c)]; });
    std::vector<std::uint32_t>& order = by_id.order;
    for (std::size_t id = 0; id < ids; ++id)
        std::sort(order.begin() + by_id.start[id], order.begin() + by_id.start[id + 1],
                  [&](std::uint32_t a, std::uint32_t b) {
                      return std::tie(keys[a], a) < std::tie(keys[b], b);
                  });
    {
        // 3. Per vertex: the angle-weighted sums of the projected face tangents, one per
        //    sign (mikktspace.c EvalTspace), and each corner's result.
        auto corner_pos = [&](std::size_t c, int k) {
            return glm::dvec3(s.positions[s.triangles[c / 3][int((c % 3 + k) % 3)]]);
        };
        auto project = [](const glm::dvec3& v, const glm::dvec3& nn) {
            const glm::dvec3 r = v - glm::dot(nn, v) * nn;
            const double len = glm::length(r);
            return len > 0.0 ? r / len : r;
        };
        auto same_vertex = [&](std::uint32_t a, std::uint32_t b) {
            return same_id[vert(a)] == same_id[vert(b)] &&
                   std::equal(keys[a].begin(), keys[a].begin() + 3, keys[b].begin());
        };
        for (std::size_t i = 0; i < nc;) {
            std::size_t j = i + 1;
            while (j < nc && same_vertex(order[i], order[j])) ++j;
            const glm::dvec3 nn = n[order[i]];
            glm::dvec3 sum_pos(0.0), sum_neg(0.0);
            for (std::size_t k = i; k < j; ++k) {
                const std::uint32_t c = order[k];
                if (sign[c / 3] == 0) continue;
                const glm::dvec3 t = project(ft[c / 3], nn);
                const glm::dvec3 p = corner_pos(c, 0);
                const glm::dvec3 v1 = project(corner_pos(c, 2) - p, nn);
                const glm::dvec3 v2 = project(corner_pos(c, 1) - p, nn);
                const double a = std::acos(std::clamp(glm::dot(v1, v2), -1.0, 1.0));
                (sign[c / 3] > 0 ? sum_pos : sum_neg) += a * t;
            }
            // Gram-Schmidt against n once more (the sums are in its plane up to rounding).
            auto finish = [&](const glm::dvec3& sum, glm::dvec3& t) {
                t = sum - glm::dot(nn, sum) * nn;
                const double len = glm::length(t);
                if (!(len > 1e-12) || !std::isfinite(len)) return false;
                t /= len;
                return true;
            };
            glm::dvec3 t_pos, t_neg;
            const bool has_pos = finish(sum_pos, t_pos), has_neg = finish(sum_neg, t_neg);
            const glm::dvec3 fallback = any_orthogonal(nn);
            for (std::size_t k = i; k < j; ++k) {
                const std::uint32_t c = order[k];
                const int sg = sign[c / 3];
                glm::dvec3 t = fallback;
                double w = sg < 0 ? -1.0 : 1.0;
                if (sg > 0 && has_pos)
                    t = t_pos;
                else if (sg < 0 && has_neg)
                    t = t_neg;
                else if (sg == 0 && has_pos)
                    t = t_pos;
                else if (sg == 0 && has_neg)
                    t = t_neg, w = -1.0;
                out[c] = glm::vec4(glm::vec3(t), float(w));
            }
            i = j;
        }
    }

    // 4. Tangents the scene gives win, as given (w reduced to its sign).
    if (has_t)
        for (std::size_t c = 0; c < nc; ++c) {
            const glm::vec4& t = s.tangents[vert(c)];
            if (!is_zero(glm::vec3(t)))
                out[c] = glm::vec4(glm::vec3(t), t.w < 0.0f ? -1.0f : 1.0f);
        }
    return out;
}

}  // namespace wp

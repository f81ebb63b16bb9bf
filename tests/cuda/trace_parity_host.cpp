// trace_parity_host.cpp — the host side of the traversal parity check on a GPU
// (tests/cuda/trace_parity.cu). Not part of CI:
//   trace_parity input IN.bin [RAYS]   the built-in Cornell box's BVH (binned SAH, 8-wide) and
//                                      RAYS (default 262144) incoherent rays of tests/support
//   trace_parity check IN.bin OUT.bin  the same traversals compiled as host C++ on every
//                                      ray; the GPU's hits must equal them bit for bit, the
//                                      stackless and stack hits each other, and any hit must
//                                      agree on occlusion. Exit 1 on any difference.
// scripts/gpu_parity.sh trace-input / trace-run / trace-check wrap the three steps.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "scene/builtin.h"
#include "shared/bvh_traverse.h"
#include "support.h"
#include "trace_parity.h"

using namespace wp;

namespace {

template <typename T>
void write_array(FILE* f, const std::vector<T>& v) {
    std::fwrite(v.data(), sizeof(T), v.size(), f);
}

template <typename T>
bool read_array(FILE* f, std::vector<T>& v, int n) {
    v.resize(n);
    return std::fread(v.data(), sizeof(T), n, f) == std::size_t(n);
}

trace_parity::Header header(const char* magic, int nodes, int tris, int rays) {
    trace_parity::Header h{};
    std::snprintf(h.magic, sizeof h.magic, "%s", magic);
    h.nodes = nodes;
    h.tris = tris;
    h.rays = rays;
    h.node_size = sizeof(BvhNode);
    h.link_size = sizeof(BvhLinks);
    h.tri_size = sizeof(TriBlock);
    h.ray_size = sizeof(Ray);
    h.hit_size = sizeof(Hit);
    return h;
}

bool same_layout(const trace_parity::Header& a, const trace_parity::Header& b) {
    return a.nodes == b.nodes && a.tris == b.tris && a.rays == b.rays && a.node_size == b.node_size &&
           a.link_size == b.link_size && a.tri_size == b.tri_size && a.ray_size == b.ray_size &&
           a.hit_size == b.hit_size;
}

int make_input(const char* path, int n) {
    Scene s = make_cornell_box();
    auto flat = bvh::flatten(bvh::build(bvh::triangle_boxes(s.positions, s.triangles)), s.positions, s.triangles);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const auto& p : s.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    auto rays = test::random_rays(std::size_t(n), 2026, lo, hi);
    FILE* f = std::fopen(path, "wb");
    if (!f) {
        std::perror(path);
        return 1;
    }
    auto h = header("WPTRACE", int(flat.nodes.size()), int(flat.triangles.size()), n);
    std::fwrite(&h, sizeof h, 1, f);
    write_array(f, flat.nodes);
    write_array(f, flat.links);
    write_array(f, flat.triangles);
    write_array(f, flat.prim_ids);
    write_array(f, rays);
    bool ok = std::fclose(f) == 0;
    std::printf("trace_parity: %s: %zu nodes (depth %d), %zu triangles in %zu blocks, %d rays\n", path, flat.nodes.size(),
                flat.depth, flat.triangle_count, flat.triangles.size(), n);
    return ok ? 0 : 1;
}

int check(const char* in_path, const char* out_path) {
    FILE* f = std::fopen(in_path, "rb");
    FILE* g = std::fopen(out_path, "rb");
    if (!f || !g) {
        std::perror(!f ? in_path : out_path);
        return 1;
    }
    trace_parity::Header h{}, oh{};
    std::vector<BvhNode> nodes;
    std::vector<BvhLinks> links;
    std::vector<TriBlock> tris;
    std::vector<int> prim_ids;
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    if (std::fread(&h, sizeof h, 1, f) != 1 || std::strcmp(h.magic, "WPTRACE") != 0 ||
        !same_layout(h, header("WPTRACE", h.nodes, h.tris, h.rays)) || !read_array(f, nodes, h.nodes) ||
        !read_array(f, links, h.nodes) || !read_array(f, tris, h.tris) || !read_array(f, prim_ids, h.tris * WP_TRI_BLOCK) ||
        !read_array(f, rays, h.rays)) {
        std::fprintf(stderr, "%s: not a trace_parity input of this build's layouts\n", in_path);
        return 1;
    }
    if (std::fread(&oh, sizeof oh, 1, g) != 1 || std::strcmp(oh.magic, "WPHITS") != 0 || !same_layout(h, oh) ||
        !read_array(g, hits, h.rays * trace_parity::kVariants)) {
        std::fprintf(stderr, "%s: not the GPU's hits for %s\n", out_path, in_path);
        return 1;
    }
    std::fclose(f);
    std::fclose(g);
    const char* names[] = {"stackless closest", "stack closest", "any hit"};
    int bad = 0;
    std::size_t n = rays.size(), hit_count = 0;
    for (int v = 0; v < trace_parity::kVariants; ++v) {
        std::size_t differ = 0, occl = 0;
        for (std::size_t i = 0; i < n; ++i) {
            TraceStats st{0, 0};
            const Hit& gpu = hits[v * n + i];
            Hit host = v == 0   ? wp_trace_closest(rays[i], nodes.data(), links.data(), tris.data(), prim_ids.data(), &st)
                       : v == 1 ? wp_trace_closest_stack(rays[i], nodes.data(), links.data(), tris.data(),
                                                         prim_ids.data(), &st)
                                : wp_trace_any(rays[i], nodes.data(), links.data(), tris.data(), prim_ids.data(), &st);
            if (std::memcmp(&gpu, &host, sizeof(Hit)) != 0) ++differ;
            if ((gpu.prim >= 0) != (hits[i].prim >= 0)) ++occl;  // against the GPU's closest hit
            if (v == 0) hit_count += gpu.prim >= 0;
        }
        std::printf("trace_parity: %-18s %zu of %zu rays differ from the host bit for bit; %zu disagree on "
                    "occlusion with the closest hit\n",
                    names[v], differ, n, occl);
        bad += differ != 0 || occl != 0;
    }
    std::size_t stack_differ = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (std::memcmp(&hits[i], &hits[n + i], sizeof(Hit)) != 0) ++stack_differ;
    std::printf("trace_parity: on the GPU, stackless and stack closest hits differ on %zu rays; %zu of %zu rays hit\n",
                stack_differ, hit_count, n);
    bad += stack_differ != 0 || hit_count == 0;
    std::printf("trace_parity: %s\n", bad ? "FAILED" : "passed");
    return bad ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && argc <= 4 && std::string(argv[1]) == "input")
        return make_input(argv[2], argc == 4 ? std::stoi(argv[3]) : 262144);
    if (argc == 4 && std::string(argv[1]) == "check") return check(argv[2], argv[3]);
    std::fprintf(stderr, "usage: trace_parity input IN.bin [RAYS] | check IN.bin OUT.bin\n");
    return 2;
}

// cmd_bench.cpp — `wavepath bench intersect` and `wavepath bench build`.
//
// intersect: builds deterministic ray sets (bench_rays.h) for a scene, traces them with
// every traversal variant (median of --runs timed runs, wall time of launch + finish),
// counts box and triangle tests per ray in a separate statistics build, and, when built
// with Embree, traces the same rays with rtcIntersect1 / rtcOccluded1 on 1 and 2 threads
// and prints the ratios. build: BVH build times of the 16k-triangle box and a 250k mesh.
// hard: the large versions of the hard cases of issue 5 (bvh/hard_cases.h): misses of rays
// aimed at shared edges and vertices (default 10^9), self-intersections of offset
// secondary rays at four scales (800x600 primary rays each), and the cost of robustness:
// the watertight + conservative kernel against a -D WP_PLAIN_TRIANGLES build
// (Möller-Trumbore, plain box tests) on the Cornell box's primary and diffuse ray sets.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/bench_rays.h"
#include "app/embree_ref.h"
#include "app/subcommands.h"
#include "bvh/build.h"
#include "bvh/device_bvh.h"
#include "bvh/flatten.h"
#include "bvh/hard_cases.h"
#include "scene/builtin.h"
#include "scene/load.h"
#include "scene/procedural.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timer.h"

namespace wp::app {

namespace {

using nlohmann::json;

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct IntersectOptions {
    std::string scene;
    std::string rays = "all";
    std::string device;
    std::string json_path;
    int runs = 7;
    int builds = 5;
    bool embree = true;
};

struct BvhBuildResult {
    bvh::FlatBvh flat;
    double build_ms = 0.0;  // median
    int nodes = 0;
    double sah = 0.0;
};

BvhBuildResult build_bvh(const Scene& s, int repeats) {
    auto boxes = bvh::triangle_boxes(s.positions, s.triangles);
    std::vector<double> ms;
    bvh::Bvh b;
    for (int i = 0; i < std::max(1, repeats); ++i) {
        Timer t;
        b = bvh::build(boxes);
        ms.push_back(t.ms());
    }
    BvhBuildResult r;
    r.build_ms = median(ms);
    r.sah = bvh::sah_cost(b);
    r.flat = bvh::flatten(b, s.positions, s.triangles);
    r.nodes = static_cast<int>(r.flat.nodes.size());
    return r;
}

int run_intersect(const IntersectOptions& o) {
    // Scene and BVH.
    Scene scene = o.scene.empty() ? make_cornell_box() : load_scene_file(o.scene);
    std::string scene_name = o.scene.empty() ? "built-in cornell-box" : o.scene;
    auto built = build_bvh(scene, o.builds);
    fmt::print("scene: {} ({} triangles), camera {}x{}\n", scene_name, scene.triangles.size(), scene.camera.width,
               scene.camera.height);
    fmt::print("BVH: {:.2f} ms build (median of {}), {}-wide, {} nodes of {} bytes, depth {}, SAH cost {:.1f}\n",
               built.build_ms, o.builds, WP_BVH_WIDTH, built.nodes, sizeof(BvhNode), built.flat.depth, built.sah);

    // Device, programs, buffers.
    auto dev = ocl::Device::open(o.device);
    fmt::print("device: {}: {}\n", dev.info.platform, dev.info.name);
    Timer tprog;
    bvh::BatchTracer tracer(dev);
    double program_ms = tprog.ms();
    bvh::BatchTracer stats_tracer(dev, true);
    auto gpu = bvh::DeviceBvh::upload(dev, built.flat);
    fmt::print("program: intersect.cl built in {:.0f} ms ({})\n", program_ms,
               tracer.program().from_cache ? "from the wavepath cache" : "compiled");

    // Ray sets: primary rays traced once to place the secondary ones.
    auto primary = primary_rays(scene.camera);
    auto primary_hits = tracer.trace(gpu, primary, bvh::TraceVariant::Stackless);
    RaySets sets = make_ray_sets(scene, primary, primary_hits);

    std::unique_ptr<EmbreeScene> embree;
    if (o.embree && embree_available()) embree = std::make_unique<EmbreeScene>(scene.positions, scene.triangles);
    unsigned hw = std::max(1u, std::thread::hardware_concurrency());

    json report;
    report["scene"] = {{"name", scene_name}, {"triangles", scene.triangles.size()}};
    report["bvh"] = {{"build_ms", built.build_ms}, {"nodes", built.nodes}, {"depth", built.flat.depth},
                     {"sah_cost", built.sah}, {"width", WP_BVH_WIDTH}, {"node_bytes", sizeof(BvhNode)},
                     {"box_tests_per_node_test", WP_BVH_WIDTH}};
    report["device"] = {{"platform", dev.info.platform}, {"name", dev.info.name}, {"driver", dev.info.driver}};
    report["program_build_ms"] = program_ms;
    report["program_from_cache"] = tracer.program().from_cache;
    report["runs"] = o.runs;
    report["sets"] = json::array();

    fmt::print("\n{:<8} {:>8}  {:<10} {:>9} {:>9} {:>8} {:>8} {:>11} {:>11}\n", "rays", "count", "traversal", "Mrays/s",
               "first ms", "box/ray", "tri/ray", "vs Embree1T", "vs Embree2T");
    struct SetDesc {
        const char* name;
        const std::vector<Ray>* rays;
        bool shadow;
    };
    std::vector<SetDesc> descs = {{"primary", &sets.primary, false},
                                  {"diffuse", &sets.diffuse, false},
                                  {"shadow", &sets.shadow, true}};
    for (const auto& sd : descs) {
        if (o.rays != "all" && o.rays != sd.name) continue;
        const auto& rays = *sd.rays;
        if (rays.empty()) {
            fmt::print("{:<8} (no rays: {})\n", sd.name, sd.shadow ? "the scene has no emitter" : "no primary hits");
            continue;
        }
        int n = static_cast<int>(rays.size());
        ::cl::Buffer rb = dev.create_buffer(CL_MEM_READ_ONLY, rays.size() * sizeof(Ray), "the benchmark rays");
        ::cl::Buffer hb = dev.create_buffer(CL_MEM_READ_WRITE, rays.size() * sizeof(Hit), "the benchmark hits");
        dev.queue.enqueueWriteBuffer(rb, CL_TRUE, 0, rays.size() * sizeof(Ray), rays.data());
        json jset = {{"rays", sd.name}, {"count", n}, {"variants", json::array()}};

        // Embree first (its numbers are the denominators).
        double embree_1t = 0.0, embree_2t = 0.0;
        std::vector<Hit> ehits;
        if (embree) {
            std::vector<double> t1, t2;
            embree->trace(rays, sd.shadow, 1, ehits);  // warm-up
            for (int r = 0; r < o.runs; ++r) t1.push_back(embree->trace(rays, sd.shadow, 1, ehits));
            for (int r = 0; r < o.runs; ++r) t2.push_back(embree->trace(rays, sd.shadow, 2, ehits));
            embree_1t = n / (median(t1) * 1e3);
            embree_2t = n / (median(t2) * 1e3);
            jset["embree"] = {{"version", embree_version()}, {"mrays_1t", embree_1t}, {"mrays_2t", embree_2t},
                              {"call", sd.shadow ? "rtcOccluded1" : "rtcIntersect1"}};
        }

        std::vector<bvh::TraceVariant> variants =
            sd.shadow ? std::vector<bvh::TraceVariant>{bvh::TraceVariant::Any, bvh::TraceVariant::Stackless}
                      : std::vector<bvh::TraceVariant>{bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack};
        for (auto v : variants) {
            // First launch (includes PoCL's work-group function compile), then timed runs.
            Timer tf;
            tracer.enqueue(gpu, rb, n, hb, v);
            dev.queue.finish();
            double first_ms = tf.ms();
            std::vector<double> ms;
            for (int r = 0; r < o.runs; ++r) {
                Timer t;
                tracer.enqueue(gpu, rb, n, hb, v);
                dev.queue.finish();
                ms.push_back(t.ms());
            }
            double mrays = n / (median(ms) * 1e3);
            // Statistics from the WP_STATS build.
            std::vector<TraceStats> st;
            auto hits = stats_tracer.trace(gpu, rays, v, &st);
            double box = 0, tri = 0;
            for (const auto& s : st) {
                box += s.box_tests;
                tri += s.tri_tests;
            }
            box /= n;
            tri /= n;
            // Agreement with Embree (a sanity figure: edge hits may legitimately differ).
            double agree = -1.0;
            if (embree) {
                std::size_t same = 0;
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    bool eh = ehits[i].prim >= 0, wh = hits[i].prim >= 0;
                    same += sd.shadow || v == bvh::TraceVariant::Any ? eh == wh : ehits[i].prim == hits[i].prim;
                }
                agree = static_cast<double>(same) / rays.size();
            }
            std::string ratio1 = embree ? fmt::format("{:.2f}x", mrays / embree_1t) : "-";
            std::string ratio = embree ? fmt::format("{:.2f}x", mrays / embree_2t) : "-";
            fmt::print("{:<8} {:>8}  {:<10} {:>9.2f} {:>9.1f} {:>8.1f} {:>8.2f} {:>11} {:>11}\n", sd.name, n,
                       to_string(v), mrays, first_ms, box, tri, ratio1, ratio);
            json jv = {{"traversal", to_string(v)}, {"mrays", mrays}, {"median_ms", median(ms)}, {"runs_ms", ms},
                       {"first_launch_ms", first_ms}, {"box_tests_per_ray", box}, {"tri_tests_per_ray", tri},
                       {"node_tests_per_ray", box / WP_BVH_WIDTH}};
            if (embree) {
                jv["ratio_vs_embree_2t"] = mrays / embree_2t;
                jv["ratio_vs_embree_1t"] = mrays / embree_1t;
                jv["agreement_with_embree"] = agree;
            }
            jset["variants"].push_back(jv);
        }
        if (embree)
            fmt::print("{:<8} {:>8}  {:<10} {:>9.2f} (1 thread) {:.2f} (2 threads)\n", sd.name, n,
                       sd.shadow ? "embree-occ1" : "embree-int1", embree_1t, embree_2t);
        report["sets"].push_back(jset);
    }
    if (embree) {
        report["embree_build_ms"] = embree->build_ms();
        fmt::print("\nEmbree {}: scene build {:.2f} ms; {} hardware threads\n", embree_version(), embree->build_ms(), hw);
    } else {
        fmt::print("\nEmbree comparator: {}\n", embree_available() ? "disabled (--no-embree)" : "not in this build");
    }
    if (!o.json_path.empty()) {
        std::string text = report.dump(2) + "\n";
        if (o.json_path == "-")
            fmt::print("{}", text);
        else
            write_text_atomically(o.json_path, text);
    }
    return 0;
}

int run_build(int repeats, const std::string& json_path) {
    json report = json::array();
    auto one = [&](const std::string& name, const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris) {
        auto boxes = bvh::triangle_boxes(pos, tris);
        std::vector<double> ms, ms1;
        bvh::Bvh b;
        bvh::BuildOptions single;
        single.threads = 1;
        std::vector<double> fms;
        bvh::FlatBvh flat;
        for (int i = 0; i < repeats; ++i) {
            Timer t;
            b = bvh::build(boxes);
            ms.push_back(t.ms());
            Timer t1;
            bvh::build(boxes, single);
            ms1.push_back(t1.ms());
            Timer tf;
            flat = bvh::flatten(b, pos, tris);
            fms.push_back(tf.ms());
        }
        fmt::print("{:<28} {:>8} triangles  {:>8.2f} ms (all threads)  {:>8.2f} ms (1 thread)  depth {}  SAH {:.1f}"
                   "  + flatten to {}-wide {:.2f} ms (depth {})\n",
                   name, tris.size(), median(ms), median(ms1), b.depth, bvh::sah_cost(b), WP_BVH_WIDTH, median(fms),
                   flat.depth);
        report.push_back({{"mesh", name}, {"triangles", tris.size()}, {"build_ms", median(ms)},
                          {"build_ms_1thread", median(ms1)}, {"depth", b.depth}, {"sah_cost", bvh::sah_cost(b)},
                          {"flatten_ms", median(fms)}, {"width", WP_BVH_WIDTH}, {"flat_depth", flat.depth}});
    };
    Scene box = make_cornell_box();
    one("built-in cornell-box", box.positions, box.triangles);
    Mesh stress = make_stress_mesh(250000);
    one("stress mesh", stress.positions, stress.triangles);
    fmt::print("(median of {} builds, {} hardware threads)\n", repeats, std::thread::hardware_concurrency());
    if (!json_path.empty()) write_text_atomically(json_path, report.dump(2) + "\n");
    return 0;
}


struct HardOptions {
    double rays = 1e9;
    int width = 800, height = 600;
    int runs = 7;
    std::string device;
    std::string json_path;
};

int run_hard(const HardOptions& o) {
    auto dev = ocl::Device::open(o.device);
    fmt::print("device: {}: {}\n", dev.info.platform, dev.info.name);
    bvh::BatchTracer tracer(dev);
    bvh::BatchTracer plain(dev, false, "-D WP_PLAIN_TRIANGLES");
    bvh::HardProbe probe(dev, tracer);
    bvh::HardProbe plain_probe(dev, plain);
    json report;
    report["device"] = {{"platform", dev.info.platform}, {"name", dev.info.name}};

    // 1. Watertightness.
    auto cases = bvh::watertight_cases();
    std::uint64_t per_case = static_cast<std::uint64_t>(o.rays / cases.size());
    fmt::print("\n1. rays aimed exactly at shared edges and vertices (from inside and outside), stackless kernel\n");
    fmt::print("{:<28} {:>9} {:>9} {:>14} {:>8} {:>8} {:>9} {:>9}   {}\n", "mesh", "triangles", "targets", "rays",
               "misses", "bad t", "seconds", "Mrays/s", "plain Moller-Trumbore misses (rays)");
    std::uint64_t total = 0, total_miss = 0;
    report["watertight"] = json::array();
    for (const auto& c : cases) {
        auto r = probe.watertight(c, per_case, bvh::TraceVariant::Stackless, 1);
        std::uint64_t pn = std::min<std::uint64_t>(per_case, 10000000);
        auto pr = plain_probe.watertight(c, pn, bvh::TraceVariant::Stackless, 1);
        total += r.rays;
        total_miss += r.misses;
        fmt::print("{:<28} {:>9} {:>9} {:>14} {:>8} {:>8} {:>9.1f} {:>9.2f}   {} ({})\n", c.name,
                   c.mesh.triangles.size(), c.segments.size() / 2, r.rays, r.misses, r.nonfinite + r.nonpositive,
                   r.seconds, r.rays / r.seconds * 1e-6, pr.misses, pr.rays);
        report["watertight"].push_back({{"mesh", c.name}, {"triangles", c.mesh.triangles.size()},
                                        {"rays", r.rays}, {"misses", r.misses}, {"nonfinite_t", r.nonfinite},
                                        {"nonpositive_t", r.nonpositive}, {"seconds", r.seconds},
                                        {"plain_rays", pr.rays}, {"plain_misses", pr.misses}});
    }
    fmt::print("{:<28} {:>34} {:>8}\n", "total", total, total_miss);

    // 3. Self-intersection at four scales.
    Scene box = make_cornell_box();
    Mesh mesh{box.positions, box.triangles};
    auto primary = bvh::camera_rays(box.camera.position, box.camera.target, box.camera.up, box.camera.vfov_deg,
                                    o.width, o.height);
    fmt::print("\n3. self-intersections: Cornell box, {}x{} primary rays, cosine + uniform + mirror bounces from "
               "offset origins\n", o.width, o.height);
    fmt::print("{:<26} {:>12} {:>14} {:>12} {:>8} {:>12} {:>12}\n", "transform", "primary hits", "secondary rays",
               "self-hits", "bad t", "max offset", "/ scene size");
    report["self_intersection"] = json::array();
    struct Sc {
        const char* name;
        float scale;
        glm::vec3 shift;
    };
    for (Sc sc : {Sc{"identity", 1.0f, {0, 0, 0}}, Sc{"scale 1e-4", 1e-4f, {0, 0, 0}}, Sc{"scale 1e5", 1e5f, {0, 0, 0}},
                  Sc{"translate (1e5, 1e5, 1e5)", 1.0f, {1e5f, 1e5f, 1e5f}}}) {
        auto r = bvh::self_intersections(dev, tracer, mesh, primary, sc.scale, sc.shift);
        fmt::print("{:<26} {:>12} {:>14} {:>12} {:>8} {:>12.3g} {:>12.3g}\n", sc.name, r.primary_hits, r.rays,
                   r.same_triangle, r.nonfinite, r.max_offset, r.max_offset / r.extent);
        report["self_intersection"].push_back({{"transform", sc.name}, {"primary_hits", r.primary_hits},
                                               {"rays", r.rays}, {"self_hits", r.same_triangle},
                                               {"nonfinite_t", r.nonfinite}, {"max_offset", r.max_offset},
                                               {"scene_extent", r.extent}});
    }

    // 9. Cost of robustness.
    auto built = build_bvh(box, 1);
    auto gpu = bvh::DeviceBvh::upload(dev, built.flat);
    auto prim_rays = primary_rays(box.camera);
    auto prim_hits = tracer.trace(gpu, prim_rays, bvh::TraceVariant::Stackless);
    RaySets sets = make_ray_sets(box, prim_rays, prim_hits);
    fmt::print("\n9. cost of robustness: built-in Cornell box, stackless closest hit, median of {} runs\n", o.runs);
    fmt::print("{:<8} {:>8} {:>18} {:>18} {:>10}\n", "rays", "count", "watertight Mrays/s", "plain MT Mrays/s",
               "slowdown");
    report["robustness_cost"] = json::array();
    for (auto [name, rays] : {std::pair<const char*, const std::vector<Ray>*>{"primary", &sets.primary},
                              {"diffuse", &sets.diffuse}}) {
        int n = static_cast<int>(rays->size());
        ::cl::Buffer rb = dev.create_buffer(CL_MEM_READ_ONLY, rays->size() * sizeof(Ray), "the benchmark rays");
        ::cl::Buffer hb = dev.create_buffer(CL_MEM_READ_WRITE, rays->size() * sizeof(Hit), "the benchmark hits");
        dev.queue.enqueueWriteBuffer(rb, CL_TRUE, 0, rays->size() * sizeof(Ray), rays->data());
        auto time = [&](bvh::BatchTracer& t) {
            t.enqueue(gpu, rb, n, hb, bvh::TraceVariant::Stackless);
            dev.queue.finish();
            std::vector<double> ms;
            for (int r = 0; r < o.runs; ++r) {
                Timer tm;
                t.enqueue(gpu, rb, n, hb, bvh::TraceVariant::Stackless);
                dev.queue.finish();
                ms.push_back(tm.ms());
            }
            return n / (median(ms) * 1e3);
        };
        // Interleave the two builds so drift of the machine affects both alike.
        std::vector<double> a, b;
        for (int k = 0; k < 3; ++k) {
            a.push_back(time(tracer));
            b.push_back(time(plain));
        }
        double robust = median(a), base = median(b);
        double slow = (base / robust - 1.0) * 100.0;
        fmt::print("{:<8} {:>8} {:>18.2f} {:>18.2f} {:>9.1f}%\n", name, n, robust, base, slow);
        report["robustness_cost"].push_back({{"rays", name}, {"count", n}, {"watertight_mrays", robust},
                                             {"plain_mrays", base}, {"slowdown_percent", slow}});
    }
    if (!o.json_path.empty()) write_text_atomically(o.json_path, report.dump(2) + "\n");
    return total_miss == 0 ? 0 : 1;
}
}  // namespace

Subcommand add_bench(CLI::App& app) {
    Subcommand s;
    s.app = app.add_subcommand("bench", "Benchmarks (speed figures for the README)");
    s.app->require_subcommand(1);
    auto o = std::make_shared<IntersectOptions>();
    auto* in = s.app->add_subcommand("intersect", "Trace primary, diffuse and shadow ray sets with every traversal "
                                                  "variant (and Embree 3 when built with it)");
    in->add_option("--scene", o->scene, "OBJ file to trace (default: the built-in ~16k-triangle Cornell box)")
        ->check(CLI::ExistingFile);
    in->add_option("--rays", o->rays, "Ray set: primary, diffuse, shadow or all")
        ->check(CLI::IsMember({"primary", "diffuse", "shadow", "all"}))
        ->capture_default_str();
    in->add_option("--runs", o->runs, "Timed runs per measurement (the median is reported)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    in->add_option("--device", o->device, "OpenCL device: index or name substring (see `wavepath devices`)");
    in->add_option("--json", o->json_path, "Also write the figures as JSON to this file ('-' = stdout)");
    in->add_flag("!--no-embree", o->embree, "Skip the Embree comparison");
    auto build_runs = std::make_shared<int>(7);
    auto build_json = std::make_shared<std::string>();
    auto* bd = s.app->add_subcommand("build", "Time BVH builds of the built-in box and a 250k-triangle mesh");
    bd->add_option("--runs", *build_runs, "Builds per mesh (the median is reported)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    bd->add_option("--json", *build_json, "Also write the figures as JSON to this file");
    auto ho = std::make_shared<HardOptions>();
    auto* hd = s.app->add_subcommand("hard", "Hard cases at full size: watertight misses (10^9 rays), "
                                             "self-intersections at four scales, the cost of robustness");
    hd->add_option("--rays", ho->rays, "Rays aimed at shared edges and vertices, over the four meshes")
        ->check(CLI::Range(1.0, 1e12))
        ->capture_default_str();
    hd->add_option("--size", ho->width, "Width of the self-intersection ray set (height = 3/4 of it)")
        ->check(CLI::Range(8, 4096))
        ->capture_default_str();
    hd->add_option("--runs", ho->runs, "Timed runs per speed measurement (the median is reported)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    hd->add_option("--device", ho->device, "OpenCL device: index or name substring (see `wavepath devices`)");
    hd->add_option("--json", ho->json_path, "Also write the figures as JSON to this file");
    s.run = [o, in, bd, build_runs, build_json, ho, hd]() -> int {
        if (hd->parsed()) {
            ho->height = ho->width * 3 / 4;
            return run_hard(*ho);
        }
        if (in->parsed()) return run_intersect(*o);
        if (bd->parsed()) return run_build(*build_runs, *build_json);
        return 2;
    };
    return s;
}

}  // namespace wp::app

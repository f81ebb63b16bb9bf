// mpi_test.cpp — `mpirun -np N wavepath render` against one process (docs/distributed.md),
// run by CTest as mpi_render_np2, mpi_render_np3 and mpi_faults.
//
//   mpi_test render NP WAVEPATH MPIEXEC DIR   the N-rank image and variance equal the one-process
//                                             ones of the same seed and spp within the bound
//                                             below; --time: the image is the one-process image
//                                             of the spp it reached; --target-error: the same
//                                             stop and image as one process
//   mpi_test diff A.exr B.exr SPP            the comparison alone (A.var.exr, B.var.exr too)
//   mpi_test faults WAVEPATH MPIEXEC DIR      a rank that fails: rank 0 names it and the cause
//                                             once, exit non-zero, nothing written; a scene
//                                             that does not load: one message; --adaptive:
//                                             usage error (2)
//
// The bound (render/distributed.h): one process adds every sample into a double-float pair
// (~48 bits); N ranks add their own samples so and the ranks' sums in double. The sums
// differ by a few units of 2^-48 relative, so the float mean may differ by at most 1 ulp.
// The variance of the mean, (S2 - S1 m) / (n (n - 1)), loses what the cancellation
// S2 - S1 m loses: allowed |difference| <= 1 ulp + 2^-40 (m^2 + n v) / (n - 1), with m the
// mean, v the variance of the mean (so that S2 / n ~ m^2 + n v).
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "image/image.h"

namespace fs = std::filesystem;
using namespace wp;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what.c_str());
    if (!ok) ++failures;
}

struct Run {
    int code = -1;
    std::string err;
};

Run run(const fs::path& dir, const std::string& cmd) {
    const fs::path err = dir / "stderr.txt";
    const std::string full = "cd '" + dir.string() + "' && " + cmd + " > /dev/null 2> '" + err.string() + "'";
    std::printf("$ %s\n", cmd.c_str());
    int st = std::system(full.c_str());
    Run r;
    r.code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    std::ifstream f(err);
    std::stringstream ss;
    ss << f.rdbuf();
    r.err = ss.str();
    return r;
}

int count(const std::string& hay, const std::string& needle) {
    int n = 0;
    for (std::size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + 1)) ++n;
    return n;
}

float ulp(float x) {
    x = std::fabs(x);
    return std::nextafter(x, INFINITY) - x;
}

// The largest difference in ulps of the mean and in units of the variance bound; counts of
// values that differ at all.
struct Diff {
    double max_ulps = 0.0, max_var_ratio = 0.0;
    long differ = 0, var_differ = 0, values = 0;
};

Diff compare(const fs::path& a, const fs::path& b, int n, bool variance) {
    Diff d;
    const Image x = read_image(a), y = read_image(b);
    if (x.width != y.width || x.height != y.height) {
        d.max_ulps = INFINITY;
        return d;
    }
    for (std::size_t i = 0; i < x.rgb.size(); ++i) {
        const float u = std::max(ulp(x.rgb[i]), ulp(y.rgb[i]));
        const double e = std::fabs(double(x.rgb[i]) - double(y.rgb[i]));
        d.max_ulps = std::max(d.max_ulps, e / u);
        d.differ += x.rgb[i] != y.rgb[i];
        ++d.values;
    }
    if (variance) {
        const fs::path av = a.parent_path() / (a.stem().string() + ".var.exr");
        const fs::path bv = b.parent_path() / (b.stem().string() + ".var.exr");
        const Image vx = read_image(av), vy = read_image(bv);
        for (std::size_t i = 0; i < vx.rgb.size(); ++i) {
            const double m = x.rgb[i], v = std::max(vx.rgb[i], vy.rgb[i]);
            const double bound = std::max(ulp(vx.rgb[i]), ulp(vy.rgb[i])) +
                                 std::ldexp(1.0, -40) * (m * m + n * v) / std::max(1, n - 1);
            const double e = std::fabs(double(vx.rgb[i]) - double(vy.rgb[i]));
            d.max_var_ratio = std::max(d.max_var_ratio, e / bound);
            d.var_differ += vx.rgb[i] != vy.rgb[i];
        }
    }
    return d;
}

void expect_within_bound(const fs::path& one, const fs::path& many, int n, bool variance, const std::string& what) {
    const Diff d = compare(one, many, n, variance);
    std::printf("     %s: %ld of %ld mean values differ, largest %.3g ulp; variance: %ld differ, "
                "largest %.3g of the bound\n",
                what.c_str(), d.differ, d.values, d.max_ulps, d.var_differ, d.max_var_ratio);
    check(d.max_ulps <= 1.0, what + ": the mean within 1 ulp of one process");
    if (variance) check(d.max_var_ratio <= 1.0, what + ": the variance of the mean within its bound");
}

int spp_of(const fs::path& p) {
    auto v = read_image_attribute(p, "wavepath:spp");
    return v ? std::atoi(v->c_str()) : -1;
}

int render_case(int np, const std::string& wp, const std::string& mpi, const fs::path& dir) {
    const std::string mpirun = "'" + mpi + "' --oversubscribe -np " + std::to_string(np) + " ";
    const std::string base = " render --size 48x36 --depth 3 --seed 11 -q --variance";
    // Same seed and spp: one process and N ranks (the Cornell box; random sampler and Sobol).
    for (const char* sampler : {"sobol", "random"}) {
        const std::string args = base + " --spp 13 --sampler " + sampler;
        const std::string one = std::string("one-") + sampler + ".exr", many = std::string("many-") + sampler + ".exr";
        Run a = run(dir, "'" + wp + "'" + args + " -o " + one);
        check(a.code == 0, "one process renders (" + a.err + ")");
        Run b = run(dir, mpirun + "'" + wp + "'" + args + " -o " + many + " --profile prof.json");
        check(b.code == 0, std::to_string(np) + " ranks render (" + b.err + ")");
        if (a.code || b.code) return 1;
        check(spp_of(dir / many) == 13, "the N-rank image says 13 spp");
        expect_within_bound(dir / one, dir / many, 13, true, std::string("--spp 13, ") + sampler);
        // The per-rank split: every rank, and their passes add up to the image's.
        std::ifstream pf(dir / "prof.json");
        const nlohmann::json j = nlohmann::json::parse(pf, nullptr, false);
        int passes = 0, ranks = 0;
        if (j.is_object() && j.contains("distributed"))
            for (const auto& r : j["distributed"]["per_rank"]) {
                passes += r["passes"].get<int>();
                // One node: the local rank is the rank; every rank names its device.
                if (r["local_rank"].get<int>() == ranks && !r["device"].get<std::string>().empty()) ranks += 1;
            }
        check(ranks == np && passes == 13, "the profile JSON's per-rank split: " + std::to_string(ranks) +
                                               " ranks, " + std::to_string(passes) + " passes");
    }
    // The environment-lit showcase (textures, glass, metals): its variance cancels more, so
    // some variance values differ (measured: 66 of 9216, at most 0.03 of the bound); the mean
    // must still be within 1 ulp.
    {
        const std::string args = std::string(" render '") + WP_SOURCE_DIR +
                                 "/scenes/showcase.json' --size 64x48 --spp 200 --seed 9 -q --variance";
        Run a = run(dir, "'" + wp + "'" + args + " -o show-one.exr");
        Run b = run(dir, mpirun + "'" + wp + "'" + args + " -o show-many.exr");
        check(a.code == 0 && b.code == 0, "the showcase renders (" + a.err + b.err + ")");
        if (a.code == 0 && b.code == 0) expect_within_bound(dir / "show-one.exr", dir / "show-many.exr", 200, true, "showcase");
    }
    // --time: the ranks stop together; the image is the mean over all samples taken, i.e. the
    // one-process image of that many samples.
    {
        Run b = run(dir, mpirun + "'" + wp + "'" + base + " --spp 100000 --time 1.5 -o timed.exr");
        check(b.code == 0, "--time renders (" + b.err + ")");
        const int n = spp_of(dir / "timed.exr");
        check(n > 0 && n < 100000, "--time stopped early at " + std::to_string(n) + " spp");
        if (n > 0) {
            Run a = run(dir, "'" + wp + "'" + base + " --spp " + std::to_string(n) + " -o timed-one.exr");
            check(a.code == 0, "one process renders the same spp");
            expect_within_bound(dir / "timed-one.exr", dir / "timed.exr", n, true, "--time");
        }
    }
    // --target-error: the estimate is of the reduced film, so N ranks stop where one process
    // stops, with the same image.
    {
        const std::string args = base + " --target-error 0.02 --spp 4096";
        Run a = run(dir, "'" + wp + "'" + args + " -o target-one.exr");
        Run b = run(dir, mpirun + "'" + wp + "'" + args + " -o target-many.exr");
        check(a.code == 0 && b.code == 0, "--target-error renders (" + a.err + b.err + ")");
        const int n1 = spp_of(dir / "target-one.exr"), nn = spp_of(dir / "target-many.exr");
        check(n1 > 0 && n1 == nn, "--target-error stops at the same spp (" + std::to_string(n1) + ", " +
                                      std::to_string(nn) + ")");
        if (n1 == nn && n1 > 0) expect_within_bound(dir / "target-one.exr", dir / "target-many.exr", n1, true, "--target-error");
    }
    return failures ? 1 : 0;
}

int faults_case(const std::string& wp, const std::string& mpi, const fs::path& dir) {
    const std::string mpirun = "'" + mpi + "' --oversubscribe -np 2 ";
    const std::string args0 = " render --size 32x24 --depth 2 -q", args = args0 + " --spp 4";
    // A rank that fails its set-up (the test aid: as a device that does not open).
    {
        Run r = run(dir, mpirun + "-x WP_TEST_FAIL_RANK=1 '" + wp + "'" + args + " -o f1.exr");
        check(r.code != 0, "a failed rank: exit non-zero (" + std::to_string(r.code) + ")");
        check(count(r.err, "rank 1 of 2 failed") == 1 && count(r.err, "WP_TEST_FAIL_RANK") == 1,
              "rank 0 names rank 1 and its cause, once: " + r.err);
        check(!fs::exists(dir / "f1.exr"), "a failed rank: nothing written");
    }
    // A rank that fails in its third round, after the others have rendered two: still nothing
    // written (rank 0 writes only after the last reduction).
    {
        Run r = run(dir, mpirun + "-x WP_TEST_FAIL_RANK=1@3 '" + wp + "'" + args0 + " -o f6.exr --spp 64");
        check(r.code != 0, "a rank failing mid-render: exit non-zero (" + std::to_string(r.code) + ")");
        check(count(r.err, "rank 1 of 2 failed") == 1 && count(r.err, "in round 3") == 1,
              "rank 0 names rank 1 and its cause, once: " + r.err);
        check(!fs::exists(dir / "f6.exr"), "a rank failing mid-render: nothing written");
    }
    // A rank killed outright: mpirun ends the job; rank 0 has written nothing.
    {
        Run r = run(dir, mpirun + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then (sleep 2; kill -9 $$) & "
                                  "fi; exec \"$0\" \"$@\"' '" +
                             wp + "'" + args0 + " --spp 1000000 --time 60 -o f7.exr");
        check(r.code != 0, "a killed rank: exit non-zero (" + std::to_string(r.code) + ")");
        check(count(r.err, "signal 9") >= 1 || count(r.err, "Killed") >= 1 || count(r.err, "killed") >= 1,
              "a killed rank: mpirun says a process was killed: " + r.err);
        check(!fs::exists(dir / "f7.exr"), "a killed rank: nothing written");
    }
    // A real failure on one rank only: its device too small for the film (out of memory).
    {
        Run r = run(dir, mpirun + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then export "
                                  "WP_DEVICE_MEMORY_LIMIT=64K; fi; exec \"$0\" \"$@\"' '" +
                             wp + "'" + args + " -o f2.exr");
        check(r.code != 0, "out of device memory on rank 1: exit non-zero");
        check(count(r.err, "rank 1 of 2 failed") == 1 && count(r.err, "memory") >= 1,
              "rank 0 names rank 1 and the memory: " + r.err);
        check(!fs::exists(dir / "f2.exr"), "out of memory: nothing written");
    }
    // A bad --device on one rank.
    {
        Run r = run(dir, mpirun + "sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then exec \"$0\" \"$@\" "
                                  "--device 99; fi; exec \"$0\" \"$@\"' '" +
                             wp + "'" + args + " -o f3.exr");
        check(r.code != 0, "a bad --device on rank 1: exit non-zero");
        check(count(r.err, "rank 1 of 2 failed") == 1, "rank 0 names rank 1: " + r.err);
        check(!fs::exists(dir / "f3.exr"), "a bad device: nothing written");
    }
    // A scene that does not load fails on every rank alike: one message.
    {
        Run r = run(dir, mpirun + "'" + wp + "' render missing-scene.obj --spp 1 -o f4.exr");
        check(r.code == 1, "a missing scene: exit 1 (" + std::to_string(r.code) + ")");
        check(count(r.err, "wavepath: error:") == 1 && count(r.err, "missing-scene.obj") >= 1,
              "a missing scene: one message: " + r.err);
        check(!fs::exists(dir / "f4.exr"), "a missing scene: nothing written");
    }
    // --adaptive: refused (per-pixel sample counts would differ per rank), once, exit 2.
    {
        Run r = run(dir, mpirun + "'" + wp + "'" + args + " --adaptive -o f5.exr");
        check(r.code == 2, "--adaptive: exit 2 (" + std::to_string(r.code) + ")");
        check(count(r.err, "--adaptive cannot be used with several MPI ranks") == 1,
              "--adaptive: one message naming why: " + r.err);
        check(!fs::exists(dir / "f5.exr"), "--adaptive: nothing written");
    }
    // A parse error: one message.
    {
        Run r = run(dir, mpirun + "'" + wp + "' render --spp banana");
        check(r.code == 2 && count(r.err, "wavepath: error:") == 1, "a parse error: once, exit 2: " + r.err);
    }
    return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "render" && argc == 6) {
        fs::path dir = fs::path(argv[5]) / ("np" + std::string(argv[2]));
        fs::remove_all(dir);
        fs::create_directories(dir);
        return render_case(std::atoi(argv[2]), argv[3], argv[4], dir);
    }
    if (mode == "faults" && argc == 5) {
        fs::path dir = fs::path(argv[4]) / "faults";
        fs::remove_all(dir);
        fs::create_directories(dir);
        return faults_case(argv[2], argv[3], dir);
    }
    if (mode == "diff" && argc == 5) {  // for docs/distributed.md: A.exr B.exr SPP (with .var.exr)
        expect_within_bound(argv[2], argv[3], std::atoi(argv[4]), true, "diff");
        return failures ? 1 : 0;
    }
    std::fprintf(stderr, "usage: mpi_test render NP WAVEPATH MPIEXEC DIR | faults WAVEPATH MPIEXEC DIR\n");
    return 2;
}

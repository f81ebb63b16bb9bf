// test_layout.cpp — the device compiler sees the shared structs exactly as the host does.
#include <catch2/catch.hpp>

#include <vector>

#include "cl/profiler.h"
#include "cl/kernel.h"
#include "cl/program.h"
#include "shared/types.h"
#include "support.h"

using namespace wp;

TEST_CASE("shared struct layouts match between host and device", "[kernel][layout]") {
    auto& dev = test::device();
    auto prog = ocl::Program::build(dev, "utility.cl");
    std::vector<int> host;
#define WP_HOST_PROBE(expr) host.push_back(static_cast<int>(expr));
    WP_LAYOUT_FIELDS(WP_HOST_PROBE)
#undef WP_HOST_PROBE
    cl::Buffer out(dev.context, CL_MEM_WRITE_ONLY, 64 * sizeof(int));
    ocl::Kernel(prog, "probe_layout").launch({&dev.queue}, 1, out);
    std::vector<int> device(64, 0);
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, 64 * sizeof(int), device.data());
    REQUIRE(host.size() < 63);
    CHECK(device[host.size()] == -1);  // the device wrote exactly as many entries
    for (std::size_t i = 0; i < host.size(); ++i) {
        INFO("layout entry " << i);
        CHECK(device[i] == host[i]);
    }
}

#include "support.h"

#include <cstdlib>

namespace wp::test {

ocl::Device& device() {
    static ocl::Device dev = [] {
        const char* sel = std::getenv("WP_TEST_DEVICE");
        return ocl::Device::open(sel ? sel : "");
    }();
    return dev;
}

}  // namespace wp::test

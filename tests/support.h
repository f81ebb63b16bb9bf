// support.h — shared helpers for the tests: the test device, random numbers, scenes.
#pragma once

#include "cl/device.h"

namespace wp::test {

// The device the kernel tests run on: $WP_TEST_DEVICE (a selector), else the first device.
ocl::Device& device();

}  // namespace wp::test

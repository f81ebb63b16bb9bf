// process_clock.h — when this process started, for the cold-start figures (render/startup.h).
//
// Two marks on the steady clock: the start of main() (mark_main_start(), the first thing
// main does) and the process's own start (exec), read from Linux's /proc/self/stat
// (starttime, in clock ticks since boot: a resolution of 1/CLK_TCK, 10 ms). exec → main is
// the dynamic loader's work (relocating every shared library the program links) and the
// libraries' static constructors.
#pragma once

#include <cstdint>

namespace wp {

// Records steady_ns() as the start of main; later calls keep the first mark.
void mark_main_start();
// The mark of mark_main_start(); where main never marked (the tests), the time of the
// first call of this function.
std::uint64_t main_start_ns();
// Milliseconds from exec of this process to main_start_ns(), from /proc/self/stat (10 ms
// resolution, rounded down, so up to 10 ms too large); < 0 where it cannot be read.
double exec_to_main_ms();

}  // namespace wp

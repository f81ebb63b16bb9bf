// interrupt.h — Ctrl-C keeps the work (issue 12, item 3).
//
// install_interrupt_handler() (called by `render` only, never by the tests) catches SIGINT and
// SIGTERM. The first one only sets a flag (a lock-free std::atomic<int>, async-signal-safe):
// the render loop stops after the step in flight (whole passes), the image of the samples so
// far is written as usual, and the command exits 128 + signal (130 for SIGINT, 143 for
// SIGTERM). A second one restores the default action and re-raises, so the process ends at
// once, killed by the signal (no image is written; atomic writes leave no partial file).
#pragma once

namespace wp::app {

void install_interrupt_handler();
// The first signal caught (SIGINT or SIGTERM), 0 while none.
int interrupt_signal();

}  // namespace wp::app

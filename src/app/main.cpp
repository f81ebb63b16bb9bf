// main.cpp — the wavepath command line.
#include <cstdio>

#include "app/commands.h"
#include "util/process_clock.h"

int main(int argc, char** argv) {
    wp::mark_main_start();  // the cold-start figures count from here (render/startup.h)
    return wp::app::run(argc, argv);
}

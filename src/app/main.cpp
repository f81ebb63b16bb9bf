// main.cpp — the wavepath command line.
#include <cstdio>

#include "app/commands.h"

int main(int argc, char** argv) { return wp::app::run(argc, argv); }

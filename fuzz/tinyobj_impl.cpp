// tinyobj_impl.cpp — tinyobjloader's implementation, from the installed header
// (libtinyobjloader-dev), compiled into the fuzz build so that it is instrumented.
// The main build links the Debian shared library instead.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

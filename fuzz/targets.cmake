# The fuzz targets (name:header:function), shared by fuzz/CMakeLists.txt (libFuzzer builds)
# and the main CMakeLists.txt (fuzz_replay_<name>: seeds and regressions in any build).
# A target is built only once its parse_* function is declared in its header.
set(WP_FUZZ_TARGETS
  "obj:scene/obj_loader.h:parse_obj"
  "json:scene/json_scene.h:parse_json_scene"
  "mitsuba:scene/mitsuba_loader.h:parse_mitsuba"
  "gltf:scene/gltf_loader.h:parse_gltf"
  "assimp:scene/assimp_loader.h:parse_assimp"
  "pbrt:scene/pbrt_loader.h:parse_pbrt")

set(WP_FUZZ_DIR ${CMAKE_CURRENT_LIST_DIR})

# Sets `out` to TRUE when src/<header> declares `function(`. The header is a configure
# dependency, so a declaration that appears later re-runs the check.
function(wp_fuzz_declared header function out)
  set(path ${WP_FUZZ_DIR}/../src/${header})
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${path})
  set(found FALSE)
  if(EXISTS ${path})
    file(READ ${path} text)
    string(FIND "${text}" "${function}(" at)
    if(NOT at EQUAL -1)
      set(found TRUE)
    endif()
  endif()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

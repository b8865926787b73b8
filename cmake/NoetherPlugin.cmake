# noether_add_plugin(NAME SOURCES src... [LIBRARIES libs...] [OUTPUT_DIRECTORY dir])
#
# Builds one plugin: a MODULE library named noether-<NAME>.so that links noether::core, is
# compiled with the flags core was built with (C++20, hidden visibility), and exports only its
# descriptor. Inside the noether source tree it lands in build/lib/noether/plugins and is
# installed beside libnoether; out of tree it lands in the current binary folder (point
# NOETHER_PLUGIN_PATH at it) unless OUTPUT_DIRECTORY says otherwise.
function(noether_add_plugin name)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "noether_add_plugin(${name}): no SOURCES given")
  endif()
  if(NOT name MATCHES "^[a-z0-9][a-z0-9-]*$")
    message(FATAL_ERROR "noether_add_plugin(${name}): plugin names use a-z, 0-9 and '-'")
  endif()
  set(target "noether-plugin-${name}")
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE noether::core ${ARG_LIBRARIES})
  target_compile_features(${target} PRIVATE cxx_std_20)
  if(ARG_OUTPUT_DIRECTORY)
    set(outdir "${ARG_OUTPUT_DIRECTORY}")
  elseif(DEFINED NOETHER_BUILD_PLUGIN_DIR)
    set(outdir "${NOETHER_BUILD_PLUGIN_DIR}")
  else()
    set(outdir "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME "noether-${name}"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    LIBRARY_OUTPUT_DIRECTORY "${outdir}")
  if(DEFINED NOETHER_BUILD_PLUGIN_DIR AND NOT ARG_OUTPUT_DIRECTORY)  # bundled with noether
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/../..")
    install(TARGETS ${target} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/noether/plugins)
    set_property(GLOBAL APPEND PROPERTY NOETHER_BUNDLED_PLUGINS ${target})
  endif()
endfunction()

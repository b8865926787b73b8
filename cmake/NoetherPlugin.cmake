# noether_add_plugin(NAME SOURCES src...)
#
# Builds one plugin: a MODULE library named noether-<NAME>.so that links noether::core, hides
# every symbol but its descriptor, and lands in the folder the plugin registry searches.
function(noether_add_plugin name)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "noether_add_plugin(${name}): no SOURCES given")
  endif()
  set(target "noether-plugin-${name}")
  add_library(${target} MODULE ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE noether::core ${ARG_LIBRARIES})
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
endfunction()

# cellmetry_add_plugin(NAME SOURCES...)
#
# A plugin is a MODULE library linked against the core. It lands in bin/plugins/ so that the
# `cellmetry` executable finds it next to itself, and it exports only its registration symbol.
function(cellmetry_add_plugin name)
  add_library(${name} MODULE ${ARGN})
  target_link_libraries(${name} PRIVATE cellmetry::core)
  set_target_properties(${name} PROPERTIES
    PREFIX "libcellmetry_"
    LIBRARY_OUTPUT_DIRECTORY ${CELLMETRY_PLUGIN_OUTPUT_DIRECTORY}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  # In cellmetry's own tree, the core's precompiled header (CellmetryPrecompiledHeaders.cmake).
  if(COMMAND cellmetry_precompile_headers AND TARGET cellmetry_basics)
    cellmetry_precompile_headers(${name} FROM cellmetry_basics)
  endif()
  install(TARGETS ${name} LIBRARY DESTINATION lib/cellmetry/plugins)
endfunction()

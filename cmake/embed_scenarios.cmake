# cmake -DOUT=FILE -DSOURCE_DIR=DIR -DFILES="a.toml;b.toml" -P embed_scenarios.cmake
# Writes the scenario files as C++ initializers {name, repository path, text} (raw string literals), so that
# sim_host carries its built-in scenarios wherever the binary goes (sim_host/src/builtin_scenarios.cpp includes it).
set(body "// Generated from sim_host/scenarios/*.toml by cmake/embed_scenarios.cmake at build time: do not edit.\n")
foreach(f IN LISTS FILES)
  get_filename_component(name ${f} NAME_WE)
  file(READ ${SOURCE_DIR}/${f} text)
  string(FIND "${text}" ")sim_toml\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${f} contains the raw string delimiter )sim_toml\"")
  endif()
  string(APPEND body "{\"${name}\", \"sim_host/scenarios/${f}\", R\"sim_toml(${text})sim_toml\"},\n")
endforeach()
# Only rewritten when it changes: an unchanged scenario set recompiles nothing.
if(EXISTS ${OUT})
  file(READ ${OUT} old)
  if(old STREQUAL body)
    return()
  endif()
endif()
file(WRITE ${OUT} "${body}")

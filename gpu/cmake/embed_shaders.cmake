# Turns GLSL files into one C++ header of raw string literals, so the kernels ship inside the
# library (no files to find at run time). Run with cmake -P:
#   -DOUTPUT=<header> -DSOURCES=<a.comp;b.glsl;...>
# Each file becomes `inline constexpr const char* k<CamelName>Source`, e.g.
# spring_forces.comp -> kSpringForcesSource.
set(content "// Generated from gpu/shaders by embed_shaders.cmake; do not edit.\n#pragma once\n\n")
string(APPEND content "namespace softbody::gpu::shaders\n{\n")
foreach(source IN LISTS SOURCES)
  get_filename_component(stem "${source}" NAME_WE)
  string(REPLACE "_" ";" words "${stem}")
  set(name "k")
  foreach(word IN LISTS words)
    string(SUBSTRING "${word}" 0 1 first)
    string(TOUPPER "${first}" first)
    string(SUBSTRING "${word}" 1 -1 rest)
    string(APPEND name "${first}${rest}")
  endforeach()
  file(READ "${source}" text)
  if(text MATCHES "\\)glsl\"")
    message(FATAL_ERROR "${source} contains the raw-string delimiter )glsl\"")
  endif()
  string(APPEND content "inline constexpr const char* ${name}Source = R\"glsl(${text})glsl\";\n\n")
endforeach()
string(APPEND content "} // namespace softbody::gpu::shaders\n")
# Rewrite only on change so dependents are not rebuilt needlessly.
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" previous)
  if(previous STREQUAL content)
    return()
  endif()
endif()
file(WRITE "${OUTPUT}" "${content}")

# strata_embed_text(SOURCE TEMPLATE OUTPUT VAR DELIM): reads SOURCE into
# ${VAR} and configures TEMPLATE into OUTPUT, where the template puts the
# text in a raw string literal delimited by ${DELIM}
# (R"@STRATA_RAW_DELIM@(...)@STRATA_RAW_DELIM@"). CMake re-runs when SOURCE
# changes, so the binary always carries the file as it is.
function(strata_embed_text source template output var delim)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${source}")
  file(READ "${source}" text)
  string(FIND "${text}" ")${delim}\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${source} contains the raw-string delimiter ')${delim}\"'; change it")
  endif()
  set(${var} "${text}")
  set(STRATA_RAW_DELIM "${delim}")
  configure_file("${template}" "${output}" @ONLY)
endfunction()

# strata_cpack_deb(OUT_VAR DIR COMPRESSION): the Debian package CPack makes
# from BUILD_DIR's install (no rebuild), into DIR (emptied first); OUT_VAR is
# set to the one .deb. Calls fail() (the including script's) when CPack fails
# or makes not exactly one package. Included by package_install.cmake and
# package_lintian.cmake.
function(strata_cpack_deb out_var dir compression)
  file(REMOVE_RECURSE ${dir})
  execute_process(COMMAND cpack -G DEB -B ${dir} --config ${BUILD_DIR}/CPackConfig.cmake
                          -D CPACK_DEBIAN_COMPRESSION_TYPE=${compression}
                  WORKING_DIRECTORY ${BUILD_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(GLOB debs ${dir}/*.deb)
  list(LENGTH debs n)
  if(NOT rc EQUAL 0 OR NOT n EQUAL 1)
    fail("cpack -G DEB: ${rc}, ${n} package(s)\n${out}${err}")
  endif()
  set(${out_var} ${debs} PARENT_SCOPE)
endfunction()

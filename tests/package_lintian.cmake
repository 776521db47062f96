# Debian's own checks of the package (issue 40): the .deb built with CPack
# from this build folder (its install, not a rebuild), then `lintian
# --fail-on error,warning`: any error or warning fails, and every tag lintian
# gives (the informational ones too) is printed. The changelog's first entry
# must be the package's version. Skipped, saying so, when lintian is not
# installed (scripts/setup installs it).
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DSANITIZED=ON|OFF -P package_lintian.cmake
cmake_minimum_required(VERSION 3.25)

function(fail what)
  message(FATAL_ERROR "package (lintian): ${what}")
endfunction()

find_program(LINTIAN lintian)
if(NOT LINTIAN)
  message("skipped: lintian is not installed (scripts/setup installs it)")
  return()
endif()
find_program(DPKG_DEB dpkg-deb REQUIRED)
find_program(DPKG_PARSECHANGELOG dpkg-parsechangelog REQUIRED)

include(${CMAKE_CURRENT_LIST_DIR}/package_cpack.cmake)
# gzip, not the package's xz: the same files, in seconds rather than minutes
# for a sanitizer build's binary (lintian refuses no compression at all).
strata_cpack_deb(debs ${WORK_DIR}/lintian-out gzip)

# The changelog shipped is cmake/debian/changelog: a new version needs its entry.
execute_process(COMMAND ${DPKG_DEB} --field ${debs} Version OUTPUT_VARIABLE version OUTPUT_STRIP_TRAILING_WHITESPACE)
execute_process(COMMAND ${DPKG_PARSECHANGELOG} -l ${SOURCE_DIR}/cmake/debian/changelog -S Version
                OUTPUT_VARIABLE logged OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT version STREQUAL logged)
  fail("the package is version '${version}', cmake/debian/changelog's first entry '${logged}': "
       "add an entry for this version\n${err}")
endif()

# An ASan build links strata position-dependent on purpose (CMakeLists.txt:
# a faster start for the tests); the package's own build (the `package`
# preset) and the others are PIE, and are checked for it.
set(suppress "")
if(SANITIZED)
  set(suppress --suppress-tags hardening-no-pie)
  message("note: a sanitizer build is linked -no-pie (CMakeLists.txt): hardening-no-pie is not checked here")
endif()
execute_process(COMMAND ${LINTIAN} --fail-on error,warning --display-info ${suppress} ${debs}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
string(REGEX MATCHALL "(^|\n)[EW]: [^\n]*" bad "${out}")
if(NOT rc EQUAL 0 OR bad)
  fail("lintian ${debs}: exit ${rc}, errors and warnings:\n${bad}\n${err}")
endif()
string(REGEX MATCHALL "(^|\n)I: " infos "${out}")
list(LENGTH infos ninfos)
message("lintian: no error or warning (${ninfos} informational tags, above)")

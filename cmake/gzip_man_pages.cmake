# Run after each link of strata (src/cli/CMakeLists.txt), once `strata
# manpages` has written DIR/*.1: each page compressed beside it as
# DIR/NAME.1.gz, the form Debian installs (Policy 12.1), with `gzip -9n`
# (no name or time stamp in the header: the same page gives the same bytes);
# a .gz whose page is gone is removed.
#   cmake -DDIR=... -P gzip_man_pages.cmake
find_program(GZIP gzip REQUIRED)
file(GLOB pages ${DIR}/*.1)
foreach(page IN LISTS pages)
  execute_process(COMMAND ${GZIP} -9nc INPUT_FILE ${page} OUTPUT_FILE ${page}.gz RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gzip ${page}: ${rc}")
  endif()
endforeach()
file(GLOB gzipped ${DIR}/*.1.gz)
foreach(gz IN LISTS gzipped)
  string(REGEX REPLACE "\\.gz$" "" page ${gz})
  if(NOT EXISTS ${page})
    file(REMOVE ${gz})
  endif()
endforeach()

# The package as a user gets it (issue 22): installed into a scratch root,
# the tank mission runs from there; the man pages render without warnings;
# the completion scripts complete. MODE=install: `cmake --install` with
# DESTDIR; MODE=deb: the Debian package built with CPack, unpacked with
# dpkg-deb into a scratch root.
#   cmake -DMODE=install|deb -DBUILD_DIR=... -DWORK_DIR=... -P package_install.cmake
cmake_minimum_required(VERSION 3.25)

function(fail what)
  message(FATAL_ERROR "package (${MODE}): ${what}")
endfunction()

set(root ${WORK_DIR}/${MODE}-root)
file(REMOVE_RECURSE ${root})
file(MAKE_DIRECTORY ${root})

if(MODE STREQUAL "install")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env DESTDIR=${root} ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix /usr
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    fail("cmake --install: ${rc}\n${out}${err}")
  endif()
elseif(MODE STREQUAL "deb")
  find_program(DPKG_DEB dpkg-deb)
  if(NOT DPKG_DEB)
    message("skipped: dpkg-deb is missing (scripts/setup installs it)")
    return()
  endif()
  include(${CMAKE_CURRENT_LIST_DIR}/package_cpack.cmake)
  # Uncompressed: the test checks the package's contents, not xz.
  strata_cpack_deb(debs ${WORK_DIR}/deb-out none)
  execute_process(COMMAND ${DPKG_DEB} --field ${debs} Package Depends RESULT_VARIABLE rc OUTPUT_VARIABLE fields)
  if(NOT rc EQUAL 0 OR NOT fields MATCHES "Package: strata" OR NOT fields MATCHES "libswipl|swi-prolog")
    fail("the package's control fields: ${fields}")
  endif()
  execute_process(COMMAND ${DPKG_DEB} -x ${debs} ${root} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    fail("dpkg-deb -x: ${err}")
  endif()
else()
  fail("MODE is install or deb")
endif()

# What must be there, at the standard places.
set(strata ${root}/usr/bin/strata)
foreach(f usr/bin/strata usr/share/man/man1/strata.1.gz usr/share/man/man1/strata-run.1.gz
          usr/share/man/man1/strata-verify.1.gz usr/bin/strata-pnml usr/share/man/man1/strata-pnml.1.gz usr/share/bash-completion/completions/strata
          usr/share/zsh/vendor-completions/_strata usr/share/bash-completion/completions/strata-pnml
          usr/share/zsh/vendor-completions/_strata-pnml usr/share/strata/missions/tank/tank.coral
          usr/share/strata/missions/tank/tank.pl usr/share/doc/strata/LICENSE usr/share/doc/strata/NOTICE
          usr/share/strata/library/coral/goto.coral usr/share/strata/library/prolog/goto.pl
          usr/lib/strata/modules/libstrata_studio_http.so usr/lib/strata/strata_driver.qlf
          usr/share/doc/strata/copyright
          usr/share/doc/strata/changelog.gz)
  if(NOT EXISTS ${root}/${f})
    fail("${f} is not installed")
  endif()
endforeach()

# The main job, from the installed files only.
execute_process(COMMAND ${strata} run ${root}/usr/share/strata/missions/tank/tank.coral --log ${root}/tank.jsonl
                WORKING_DIRECTORY ${root} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${root}/tank.jsonl OR NOT out MATCHES "completed")
  fail("strata run of the installed tank mission: exit ${rc}\n${out}${err}")
endif()
# The studio's HTTP server is a module strata loads from the installed
# library folder (src/studio/http_module.h): served, and a page answered.
execute_process(COMMAND ${strata} run ${root}/usr/share/strata/missions/tank/tank.coral --studio
                        --listen 127.0.0.1:0 --speed 1000
                WORKING_DIRECTORY ${root} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^http://127.0.0.1:[0-9]+\n")
  fail("strata run --studio from the installed files: exit ${rc}\n${out}${err}")
endif()
# The phase library from the installed files only: a mission that imports
# goto by name, in a folder of its own, finds the installed library/coral
# (not the source tree's) and is checked whole; the rules twin the same.
set(lib_mission_dir ${root}/library-mission)
file(MAKE_DIRECTORY ${lib_mission_dir})
file(WRITE ${lib_mission_dir}/m.coral
     "import goto;\nmission m { place a = 1; exit done; transition t { wait { a } action { PHASE(goto(1, 2, 3, 0.5), done) } } }\n")
file(WRITE ${lib_mission_dir}/m.pl ":- use_phase(goto).\nmission :- goto(1, 2, 3, 0.5, _).\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=STRATA_LIBRARY ${strata} dump ${lib_mission_dir}/m.coral
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "net goto\\(x, y, depth, speed\\)")
  fail("strata dump of a mission importing the installed library: exit ${rc}\n${out}${err}")
endif()
file(WRITE ${lib_mission_dir}/nope.coral "import no_such_phase;\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=STRATA_LIBRARY ${strata} check ${lib_mission_dir}/nope.coral
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 65 OR NOT err MATCHES "library's folders \\(${root}/usr/share/strata/library/coral\\)")
  fail("an unknown module must name the installed library's folder, and only it: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=STRATA_LIBRARY ${strata} check ${lib_mission_dir}/m.pl
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  fail("strata check of rules using the installed library: exit ${rc}\n${out}${err}")
endif()
# The precompiled PROLOG driver from the installed library folder
# (src/strategic/prolog_driver_precompiled.h): the tank rules check without
# a note that it was missing or not this strata's.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=STRATA_PROLOG_DRIVER ${strata} check
                        ${root}/usr/share/strata/missions/tank/tank.pl
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR err MATCHES "note:")
  fail("strata check of the installed tank rules with the installed driver: exit ${rc}\n${out}${err}")
endif()
# strata-pnml from the installed files: a net of its own explored.
file(WRITE ${root}/two.pnml [=[<?xml version="1.0"?>
<pnml xmlns="http://www.pnml.org/version-2009/grammar/pnml">
 <net id="two" type="http://www.pnml.org/version-2009/grammar/ptnet"><page id="g">
  <place id="a"><initialMarking><text>1</text></initialMarking></place>
  <place id="b"/>
  <transition id="t"/>
  <arc id="e1" source="a" target="t"/><arc id="e2" source="t" target="b"/>
 </page></net>
</pnml>
]=])
execute_process(COMMAND ${root}/usr/bin/strata-pnml ${root}/two.pnml --format json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "\"states\": 2,.*\"deadlock\": true")
  fail("strata-pnml of a net from the installed files: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${strata} --version OUTPUT_VARIABLE version)
if(NOT version MATCHES "^strata [0-9]+\\.[0-9]+\\.[0-9]+ \\([^)]+\\)")
  fail("--version: '${version}'")
endif()

if(MODE STREQUAL "deb")
  return()   # the pages and scripts are the same files as MODE=install's
endif()

# One page per subcommand, gzipped, each rendering without a warning.
execute_process(COMMAND ${strata} --help OUTPUT_VARIABLE help)
string(REGEX MATCHALL "\n  [a-z]+ " commands "${help}")
list(LENGTH commands ncommands)
if(ncommands LESS 10)
  fail("only ${ncommands} subcommands found in --help:\n${help}")
endif()
foreach(c IN LISTS commands)
  string(STRIP "${c}" c)
  if(NOT EXISTS ${root}/usr/share/man/man1/strata-${c}.1.gz)
    fail("no man page for `strata ${c}`")
  endif()
endforeach()
file(GLOB pages ${root}/usr/share/man/man1/*)
foreach(page IN LISTS pages)
  if(NOT page MATCHES "\\.1\\.gz$")
    fail("${page}: not a gzipped page (Debian Policy 12.1)")
  endif()
endforeach()
find_program(GROFF groff)
if(GROFF)
  foreach(page IN LISTS pages)
    execute_process(COMMAND gzip -dc ${page} COMMAND ${GROFF} -man -ww -z
                    RESULTS_VARIABLE rcs ERROR_VARIABLE warnings)
    if(NOT rcs STREQUAL "0;0" OR NOT warnings STREQUAL "")
      fail("groff on ${page}: ${warnings}")
    endif()
  endforeach()
else()
  message("note: groff is missing: the pages' rendering is not checked")
endif()

# bash completes a subcommand and a subcommand's options.
set(script [=[
source "$1"
COMP_WORDS=(strata ver); COMP_CWORD=1; _strata; echo "1:${COMPREPLY[*]}"
COMP_WORDS=(strata verify --max-s); COMP_CWORD=2; _strata; echo "2:${COMPREPLY[*]}"
]=])
execute_process(COMMAND bash -c "${script}" bash ${root}/usr/share/bash-completion/completions/strata
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "1:verify\n" OR NOT out MATCHES "2:--max-states\n")
  fail("bash completion: exit ${rc}: ${out}${err}")
endif()
# strata-pnml's: its options (it has no subcommands).
set(script [=[
source "$1"
COMP_WORDS=(strata-pnml --max-s); COMP_CWORD=1; _strata_pnml; echo "1:${COMPREPLY[*]}"
complete -p strata-pnml
]=])
execute_process(COMMAND bash -c "${script}" bash ${root}/usr/share/bash-completion/completions/strata-pnml
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "1:--max-states\n" OR NOT out MATCHES "-F _strata_pnml strata-pnml")
  fail("bash completion of strata-pnml: exit ${rc}: ${out}${err}")
endif()
find_program(ZSH zsh)
if(ZSH)
  foreach(script _strata _strata-pnml)
    execute_process(COMMAND ${ZSH} -n ${root}/usr/share/zsh/vendor-completions/${script} RESULT_VARIABLE rc
                    ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      fail("zsh -n ${script}: ${err}")
    endif()
  endforeach()
else()
  message("note: zsh is missing: the zsh script's syntax is not checked")
endif()

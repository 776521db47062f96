# The precompiled PROLOG driver and its fallback (docs/prolog.md §6).
# `strata check ${MISSION}` and `strata check` of the sandbox fixture
# ${FIXTURE}, with the driver precompiled (${QLF}, found beside strata: no
# note), from a missing file, a truncated copy, a copy with one byte
# changed (each: a note on stderr naming the file and why, then the
# driver from its text) and with STRATA_PROLOG_DRIVER="" (the text, no
# note). Every way exits as the precompiled one does and prints the same.
#   cmake -DSTRATA=... -DQLF=... -DMISSION=... -DFIXTURE=... -DWORK_DIR=... -P prolog_precompiled_driver.cmake
cmake_minimum_required(VERSION 3.25)

function(fail what)
  message(FATAL_ERROR "precompiled driver: ${what}")
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
if(NOT EXISTS ${QLF})
  fail("${QLF} was not built")
endif()
file(SIZE ${QLF} size)
math(EXPR half "${size} / 2")
# The truncated copy: the first half. The altered one: its middle byte
# flipped (0xff xor), with dd.
execute_process(COMMAND head -c ${half} ${QLF} OUTPUT_FILE ${WORK_DIR}/truncated.qlf RESULT_VARIABLE rc1)
file(COPY_FILE ${QLF} ${WORK_DIR}/altered.qlf)
file(READ ${QLF} byte OFFSET ${half} LIMIT 1 HEX)
math(EXPR flipped "0x${byte} ^ 255")
# printf(1) takes octal escapes.
math(EXPR o1 "${flipped} / 64")
math(EXPR o2 "(${flipped} / 8) % 8")
math(EXPR o3 "${flipped} % 8")
file(WRITE ${WORK_DIR}/flip.sh "printf '\\${o1}${o2}${o3}' | dd of='${WORK_DIR}/altered.qlf' bs=1 seek=${half} conv=notrunc 2>/dev/null\n")
execute_process(COMMAND sh ${WORK_DIR}/flip.sh RESULT_VARIABLE rc2)
file(READ ${WORK_DIR}/altered.qlf after OFFSET ${half} LIMIT 1 HEX)
file(SIZE ${WORK_DIR}/altered.qlf altered_size)
if(NOT rc1 EQUAL 0 OR NOT rc2 EQUAL 0 OR after STREQUAL byte OR NOT altered_size EQUAL size)
  fail("cannot make the truncated and altered copies (${rc1} ${rc2} ${byte} ${after} ${altered_size})")
endif()

# check(NAME DRIVER FILE): out_NAME, err_NAME and rc_NAME in the caller;
# DRIVER "-" leaves STRATA_PROLOG_DRIVER unset.
function(check name driver file)
  if(driver STREQUAL "-")
    set(env ${CMAKE_COMMAND} -E env --unset=STRATA_PROLOG_DRIVER)
  else()
    set(env ${CMAKE_COMMAND} -E env STRATA_PROLOG_DRIVER=${driver})
  endif()
  get_filename_component(dir ${file} DIRECTORY)
  get_filename_component(base ${file} NAME)
  execute_process(COMMAND ${env} ${STRATA} check ${base} WORKING_DIRECTORY ${dir}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  set(rc_${name} "${rc}" PARENT_SCOPE)
  set(out_${name} "${out}" PARENT_SCOPE)
  set(err_${name} "${err}" PARENT_SCOPE)
endfunction()

set(note_re "strata: note: the precompiled PROLOG driver [^\n]*; loading the driver from its text instead")
foreach(target mission fixture)
  if(target STREQUAL "mission")
    set(file ${MISSION})
    set(expect_rc 0)
  else()
    set(file ${FIXTURE})
    set(expect_rc 65)
  endif()
  check(precompiled - ${file})
  if(NOT rc_precompiled EQUAL expect_rc OR err_precompiled MATCHES "note:")
    fail("${target}, precompiled: exit ${rc_precompiled} (expected ${expect_rc})\n${out_precompiled}${err_precompiled}")
  endif()
  set(cases "missing:${WORK_DIR}/missing.qlf:is missing"
            "truncated:${WORK_DIR}/truncated.qlf:is not the one this strata was built with"
            "altered:${WORK_DIR}/altered.qlf:is not the one this strata was built with"
            "off::")
  foreach(case IN LISTS cases)
    string(REPLACE ":" ";" parts "${case}")
    list(GET parts 0 name)
    list(GET parts 1 driver)
    list(GET parts 2 why)
    check(${name} "${driver}" ${file})
    if(NOT rc_${name} EQUAL expect_rc)
      fail("${target}, ${name}: exit ${rc_${name}} (expected ${expect_rc})\n${out_${name}}${err_${name}}")
    endif()
    if(why STREQUAL "")
      if(err_${name} MATCHES "note:")
        fail("${target}, ${name}: a note without cause:\n${err_${name}}")
      endif()
      set(err "${err_${name}}")
    else()
      string(FIND "${err_${name}}" "${driver}" names_it)
      if(NOT err_${name} MATCHES "${note_re}" OR NOT err_${name} MATCHES "${why}" OR names_it EQUAL -1)
        fail("${target}, ${name}: no note that ${driver} ${why}:\n${err_${name}}")
      endif()
      string(REGEX REPLACE "${note_re}[^\n]*\n" "" err "${err_${name}}")
    endif()
    if(NOT out_${name} STREQUAL out_precompiled OR NOT err STREQUAL err_precompiled)
      fail("${target}, ${name}: not what the precompiled driver says\n--- precompiled:\n"
           "${out_precompiled}${err_precompiled}\n--- ${name}:\n${out_${name}}${err}")
    endif()
  endforeach()
endforeach()
file(REMOVE_RECURSE ${WORK_DIR})

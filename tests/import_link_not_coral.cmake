# A mission folder whose phase file is a link to a file that is not CORAL
# (here a "secret" beside it): `strata check` showed the file's lines in its
# syntax errors, and `strata campaign` ran the cases with it as the phase.
# Now neither reads it: check refuses the import naming where the link
# leads, the campaign's case errs, and the secret is in no output.
#   cmake -DSTRATA=... -DSOURCE_DIR=... -DWORK=... -P import_link_not_coral.cmake
cmake_minimum_required(VERSION 3.25)

file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(COPY ${SOURCE_DIR}/missions/tank DESTINATION ${WORK})
file(READ ${WORK}/tank/initialize.coral phase)
file(WRITE ${WORK}/secret.txt "SECRET_TOKEN_41 do not show\n${phase}")
file(REMOVE ${WORK}/tank/initialize.coral)
file(CREATE_LINK ../secret.txt ${WORK}/tank/initialize.coral SYMBOLIC)
# The campaign of the CORAL mission alone, one case.
file(READ ${WORK}/tank/campaign.toml spec)
string(REGEX REPLACE "missions = \\[[^]]*\\]" "missions = [\"tank.coral\"]" spec "${spec}")
file(WRITE ${WORK}/tank/campaign.toml "${spec}")

execute_process(COMMAND ${STRATA} check ${WORK}/tank/tank.coral
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 65 OR NOT err MATCHES "initialize.coral' is a link to '[^']*secret.txt', which is not a .coral file; not read"
   OR "${out}${err}" MATCHES "SECRET_TOKEN")
  message(FATAL_ERROR "strata check: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${STRATA} campaign ${WORK}/tank/campaign.toml --case 0 --out ${WORK}/out -q
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
file(READ ${WORK}/out/results.jsonl results)
if(NOT rc EQUAL 1 OR NOT results MATCHES "\"outcome\":\"error\"" OR "${out}${err}${results}" MATCHES "SECRET_TOKEN")
  message(FATAL_ERROR "strata campaign: exit ${rc}\n${out}${err}\n${results}")
endif()
message("check refused the link, the campaign's case erred, the secret was shown nowhere")

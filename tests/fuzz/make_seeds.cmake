# Writes the fuzz seeds (tests/fuzz/CMakeLists.txt): -DGEN=nephele-gen -DNEPHELE=nephele -DOUT=dir
# -DSCENES=examples/scenes. Model files: the standard tiny set (WRF Lambert/Mercator x Thompson/
# WSM3, ICON regular and native) and a single-file ICON GRIB2; nph: one converted WRF file;
# scenes: the example scenes with their data paths filled in.
# Script mode starts with no policies set: under the old CMP0053 rules "@OUT@" below is read as
# the variable OUT, so the placeholder was never replaced (and cmake warned once per scene).
cmake_policy(SET CMP0053 NEW)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT}/model ${OUT}/nph ${OUT}/scene ${OUT}/tmp)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "fuzz seeds: ${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()
run(${GEN} all --dir ${OUT}/model)
run(${GEN} icon --grib2 ${OUT}/tmp/grib2 --grib2-layout single)
file(GLOB grib ${OUT}/tmp/grib2/*)
foreach(g IN LISTS grib)
  get_filename_component(n ${g} NAME)
  file(RENAME ${g} ${OUT}/model/${n})
endforeach()
file(GLOB wrf ${OUT}/model/wrfout_lambert_thompson*)
list(GET wrf 0 first)
run(${NEPHELE} convert ${first} -o ${OUT}/nph/tiny.nph --no-progress)
file(GLOB scenes ${SCENES}/*.json ${SCENES}/*.json.in)
foreach(s IN LISTS scenes)
  get_filename_component(n ${s} NAME)
  file(READ ${s} text)
  string(REPLACE "@DATA@" "tiny.nph" text "${text}")
  string(REPLACE "@OUT@" "out" text "${text}")
  file(WRITE ${OUT}/scene/${n} "${text}")
endforeach()
file(REMOVE_RECURSE ${OUT}/tmp)

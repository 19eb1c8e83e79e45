# ctest driver: install the main build into a scratch prefix, then configure, build and run the
# consumer both ways. Variables: BUILD_DIR (the main build), SOURCE_DIR, WORK_DIR, and
# nanoflann_DIR (optional: the nanoflann CMake package the main build used).
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
set(nanoflann_arg "")
if(nanoflann_DIR)
  set(nanoflann_arg -Dnanoflann_DIR=${nanoflann_DIR})
endif()
foreach(mode package subdirectory)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/${mode}
      -DCONSUMER_MODE=${mode} -DPPCR_SOURCE_DIR=${SOURCE_DIR} ${nanoflann_arg}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/${mode} -j2)
  run(${WORK_DIR}/${mode}/consumer)
endforeach()

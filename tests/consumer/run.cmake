# ctest driver: install the main build into a scratch prefix, then configure, build and run the
# consumer both ways. Variables: BUILD_DIR (the main build), SOURCE_DIR, WORK_DIR, and the
# nanoflann the main build used (optional, passed on when set): nanoflann_DIR (its CMake package)
# or NANOFLANN_INCLUDE_DIR (the folder of its header, third_party/cmake/Findnanoflann.cmake),
# and CXX_COMPILER and CXX_FLAGS, the main build's compiler and CMAKE_CXX_FLAGS, which compile the
# consumers.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
set(nanoflann_args "")
foreach(var nanoflann_DIR NANOFLANN_INCLUDE_DIR)
  if(${var})  # false when empty or *-NOTFOUND
    list(APPEND nanoflann_args -D${var}=${${var}})
  endif()
endforeach()
foreach(mode package subdirectory)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/${mode}
      -DCONSUMER_MODE=${mode} -DPPCR_SOURCE_DIR=${SOURCE_DIR} ${nanoflann_args}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
      "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/${mode} -j2)
  run(${WORK_DIR}/${mode}/consumer)
endforeach()

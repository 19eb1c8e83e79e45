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

# A consumer compiled with another Eigen layout than the library (include/ppcr/abi.hpp) must fail
# to link, with an undefined reference in its own ABI namespace, instead of linking and reading
# the library's structs at the wrong offsets (docs/RELIABILITY.md, F7: at 3c0bad5 such a consumer
# crashed). The other layout: AVX's 32-byte alignment (-mavx, F7's case) on an x86-64 host when
# this build sets no instruction set; else static alignment off (EIGEN_MAX_STATIC_ALIGN_BYTES=0,
# which Eigen accepts on any target), or 16 bytes if this build has it off already.
cmake_host_system_information(RESULT host_platform QUERY OS_PLATFORM)  # x86_64, aarch64, ...
if(host_platform MATCHES "x86_64|AMD64" AND NOT CXX_FLAGS MATCHES "-march|-mavx")
  set(other_flag -mavx)
  set(other 32)
elseif(CXX_FLAGS MATCHES "EIGEN_MAX_STATIC_ALIGN_BYTES=0|EIGEN_DONT_ALIGN")
  set(other_flag -DEIGEN_MAX_STATIC_ALIGN_BYTES=16)
  set(other 16)
else()
  set(other_flag -DEIGEN_MAX_STATIC_ALIGN_BYTES=0)
  set(other 0)
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/mismatch
    -DCONSUMER_MODE=package ${nanoflann_args} -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS} ${other_flag}")
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/mismatch RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "a consumer compiled with ${other_flag} linked against the library built "
                      "with CMAKE_CXX_FLAGS '${CXX_FLAGS}': the ABI namespace "
                      "(include/ppcr/abi.hpp) did not keep them apart")
endif()
if(NOT "${out}${err}" MATCHES "undefined reference to [^\n]*ppcr::eigen_align_${other}::")
  message(FATAL_ERROR "the consumer compiled with ${other_flag} failed to build, but not with an "
                      "undefined reference to ppcr::eigen_align_${other}::...:\n${out}\n${err}")
endif()
message(STATUS "consumer compiled with ${other_flag} refused at link time (ppcr::eigen_align_${other})")

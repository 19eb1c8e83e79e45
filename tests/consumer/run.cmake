# ctest driver: install the main build into a scratch prefix, then configure, build and run the
# consumer both ways. Variables: BUILD_DIR (the main build), SOURCE_DIR, WORK_DIR, and
# CXX_COMPILER and CXX_FLAGS, the main build's compiler and CMAKE_CXX_FLAGS, which compile the
# consumers; PROGRAMS, the executables the main build made (comma-separated), which the install
# must hold.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
file(REMOVE_RECURSE ${WORK_DIR})
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)

# The install holds the programs built, and the headers of the installed libraries only: ppcr's
# and ppcr_io's, not ppcr_synthetic's (that library is not installed).
string(REPLACE "," ";" programs "${PROGRAMS}")
foreach(program ${programs})
  if(NOT EXISTS ${WORK_DIR}/prefix/bin/${program})
    message(FATAL_ERROR "cmake --install did not install ${program} into ${WORK_DIR}/prefix/bin")
  endif()
endforeach()
if(EXISTS ${WORK_DIR}/prefix/include/ppcr/synthetic.hpp OR
   NOT EXISTS ${WORK_DIR}/prefix/include/ppcr/io.hpp)
  message(FATAL_ERROR "installed headers: synthetic.hpp (not installed library) or no io.hpp")
endif()
# The vendored consumer is also one where liblzf is missing (find_package(LZF) disabled): ppcr_io
# builds without it and refuses a binary_compressed PCD with a message naming liblzf (main.cpp,
# CONSUMER_NO_LZF); the installed package is built with it.
set(subdirectory_args -DCONSUMER_NO_LZF=ON -DCMAKE_DISABLE_FIND_PACKAGE_LZF=ON)
set(package_args "")
foreach(mode package subdirectory)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/${mode}
      -DCONSUMER_MODE=${mode} -DPPCR_SOURCE_DIR=${SOURCE_DIR} ${${mode}_args}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
      "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/${mode} -j2)
  run(${WORK_DIR}/${mode}/consumer)
endforeach()

# A consumer compiled with another Eigen alignment than the library (include/ppcr/abi.hpp) must
# fail to compile, with abi.hpp's message naming the cause and the fix, instead of linking and
# reading the library's structs at the wrong offsets (docs/RELIABILITY.md, F7). (Without the
# package's definitions, the ABI namespace still refuses it at link time.)
# The library's namespace is read off the installed archive (its mangled names), so the test
# does not guess it from the flags. The other alignment: static alignment off
# (-DEIGEN_MAX_STATIC_ALIGN_BYTES=0, which Eigen accepts on any target) and, with GCC or Clang on
# an x86-64 host when the library has Eigen's default x86-64 alignment (16) and CXX_FLAGS set
# neither an instruction set nor an EIGEN_ macro, also -mavx (32: F7's case).
file(GLOB ppcr_archives ${WORK_DIR}/prefix/lib*/libppcr.a ${WORK_DIR}/prefix/lib*/libppcr.so)
if(NOT ppcr_archives)
  message(FATAL_ERROR "no libppcr.a or libppcr.so under ${WORK_DIR}/prefix/lib*")
endif()
list(GET ppcr_archives 0 ppcr_archive)
# In a mangled name the namespace is followed by the next name's length ("...heap166detail"), so
# the values are matched as Eigen's possible ones, not as any digits.
set(align_value "(0|8|16|32|64)")
file(STRINGS ${ppcr_archive} abi_strings REGEX "eigen_align[0-9]+_heap[0-9]+")
string(REGEX MATCH "eigen_align${align_value}_heap${align_value}" library_abi "${abi_strings}")
if(NOT library_abi)
  message(FATAL_ERROR "no eigen_align<N>_heap<N> namespace in the symbols of ${ppcr_archive}")
endif()
set(library_static_align ${CMAKE_MATCH_1})
set(other_flags "")
if(NOT library_static_align STREQUAL "0")
  list(APPEND other_flags -DEIGEN_MAX_STATIC_ALIGN_BYTES=0)
endif()
cmake_host_system_information(RESULT host_platform QUERY OS_PLATFORM)  # x86_64, aarch64, ...
if(library_abi STREQUAL "eigen_align16_heap16" AND host_platform MATCHES "x86_64|AMD64" AND
   NOT CXX_FLAGS MATCHES "EIGEN_|-m|/arch" AND
   CXX_COMPILER MATCHES "(g\\+\\+|clang\\+\\+|c\\+\\+)[^/]*$")
  list(APPEND other_flags -mavx)
endif()
if(NOT other_flags)
  message(STATUS "mismatched consumer not built: the library's ${library_abi} leaves no other "
                 "layout this test knows how to make")
endif()
set(refusal "compiled with other instruction-set flags \\(-march, -mavx, EIGEN_ macros\\) than the ppcr library")
foreach(other_flag ${other_flags})
  string(MAKE_C_IDENTIFIER "mismatch${other_flag}" dir)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${WORK_DIR}/${dir}
      -DCONSUMER_MODE=package -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
      -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
      "-DCMAKE_CXX_FLAGS=${CXX_FLAGS} ${other_flag}")
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/${dir} RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "a consumer compiled with ${other_flag} built against the library "
                        "(${library_abi}, CMAKE_CXX_FLAGS '${CXX_FLAGS}')")
  endif()
  if(NOT "${out}${err}" MATCHES "${refusal}")
    message(FATAL_ERROR "the consumer compiled with ${other_flag} failed to build, but not with "
                        "include/ppcr/abi.hpp's message:\n${out}\n${err}")
  endif()
  message(STATUS "consumer compiled with ${other_flag} refused at compile time (the library "
                 "has ppcr::${library_abi})")
endforeach()

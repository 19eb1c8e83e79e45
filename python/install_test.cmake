# ctest driver of python_install: `cmake --install` of the main build into a scratch DESTDIR, then
# the interpreter imports ppcr from where the install put it (PPCR_PYTHON_INSTALL_DIR under the
# prefix, or that absolute folder) and registers a small pair with it. (Locked against
# consumer_cmake, which installs the same build: both write its install_manifest.txt.) Variables: BUILD_DIR,
# WORK_DIR, PREFIX (CMAKE_INSTALL_PREFIX), MODULE_DIR (PPCR_PYTHON_INSTALL_DIR), PYTHON.
file(REMOVE_RECURSE ${WORK_DIR})
set(ENV{DESTDIR} ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD_DIR} (DESTDIR ${WORK_DIR}) failed: ${err}")
endif()
if(IS_ABSOLUTE ${MODULE_DIR})
  set(site ${WORK_DIR}${MODULE_DIR})
else()
  set(site ${WORK_DIR}${PREFIX}/${MODULE_DIR})
endif()
set(ENV{PYTHONPATH} ${site})
set(check [=[
import sys, numpy as np, ppcr
assert ppcr.__file__.startswith(sys.argv[1]), ppcr.__file__
rng = np.random.default_rng(0)
v = rng.normal(size=(3000, 3))
v /= np.linalg.norm(v, axis=1)[:, None]
target = v * (1 + 0.2 * np.sin(3 * v[:, :1] + 1) * np.cos(2 * v[:, 1:2]))
r = ppcr.register(target + [0.01, 0, 0], target, radius=0.1)
assert r.converged and abs(r.transformation[0, 3] + 0.01) < 1e-4, r.transformation
print("imported", ppcr.__file__, "and registered:", r)
]=])
execute_process(COMMAND ${PYTHON} -c "${check}" ${site} RESULT_VARIABLE rc
                WORKING_DIRECTORY ${WORK_DIR})  # not beside the build tree's module
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the installed module did not import or register from ${site}")
endif()

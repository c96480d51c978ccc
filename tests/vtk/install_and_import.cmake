# Installs the build tree into PREFIX and runs SCRIPT with the system Python
# against the installed `rayscope` package only (no build-tree paths).
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX}
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH
  PYTHONPATH=${PREFIX}/${PYTHON_DEST} LD_LIBRARY_PATH=${PREFIX}/${LIBDIR}
  ${PYTHON} ${SCRIPT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${SCRIPT} failed against the install (${rc})")
endif()

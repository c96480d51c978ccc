# paraview.gui: runs the GUI with test_gui.py under Xvfb, then checks what it
# wrote. cmake -DPARAVIEW=... -DSCRIPT=... -DOUT=... -P test_gui_check.cmake
file(REMOVE "${OUT}/gui_filters.txt")
execute_process(COMMAND xvfb-run -a "${PARAVIEW}" "--script=${SCRIPT}" --exit
  RESULT_VARIABLE rc TIMEOUT 300)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "paraview --script exited with ${rc}")
endif()
if(NOT EXISTS "${OUT}/gui_filters.txt")
  message(FATAL_ERROR "paraview ran, but the script wrote nothing (did the GUI start?)")
endif()
file(READ "${OUT}/gui_filters.txt" got)
set(want "RayScopeRayTrace | Ray Trace | RayScope
RayScopeRayTree | Ray Tree | RayScope
RayScopeBVH | BVH | RayScope
")
if(NOT got STREQUAL want)
  message(FATAL_ERROR "the GUI lists:\n${got}\nexpected:\n${want}")
endif()
message(STATUS "the ParaView GUI lists the filters:\n${got}")

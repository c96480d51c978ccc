# paraview.gui: runs the GUI with test_gui.py, then checks what it
# wrote. cmake -DPARAVIEW=... -DSCRIPT=... -DOUT=... -P test_gui_check.cmake
# On the display ctest runs under (scripts/test: xvfb-run); a second Xvfb
# started from here, beside the tests running in parallel on the first, made
# their OpenGL windows lose their X connection. xvfb-run only without one.
file(REMOVE "${OUT}/gui_filters.txt")
set(launcher)
if(NOT DEFINED ENV{DISPLAY} OR "$ENV{DISPLAY}" STREQUAL "")
  set(launcher xvfb-run -a)
endif()
execute_process(COMMAND ${launcher} "${PARAVIEW}" --dr "--script=${SCRIPT}" --exit
  RESULT_VARIABLE rc TIMEOUT 300)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "paraview --script exited with ${rc}")
endif()
if(NOT EXISTS "${OUT}/gui_filters.txt")
  message(FATAL_ERROR "paraview ran, but the script wrote nothing (did the GUI start?)")
endif()
file(READ "${OUT}/gui_filters.txt" got)
# RayScopeBVH, the structure filter's deprecated old name, inherits its proxy
# but not its menu category (None): only the new name is under RayScope.
set(want "RayScopeRayTrace | Ray Trace | RayScope
RayScopeRayTree | Ray Tree | RayScope
RayScopeAccelStructure | Acceleration Structure | RayScope
RayScopeBVH | BVH | None
RayScopeView | RayScope | vtkRayScopeRenderView
")
if(NOT got STREQUAL want)
  message(FATAL_ERROR "the GUI lists:\n${got}\nexpected:\n${want}")
endif()
message(STATUS "the ParaView GUI lists the filters:\n${got}")

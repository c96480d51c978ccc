# Included by the top-level CMakeLists.txt: builds the ParaView plugin in its
# own configuration (this directory's CMakeLists.txt, against ParaView's VTK)
# as an external project, and installs it into the build tree:
#
#   <build>/paraview/build                  the plugin's CMake build
#   <build>/paraview/install/lib/paraview-5.11/plugins/RayScope/RayScope.so
#                                           the installed plugin; the folder
#                                           for PV_PLUGIN_PATH is
#                                           RAYSCOPE_PARAVIEW_PLUGIN_PATH
#   <build>/paraview/pvpython, paraview, pvbatch
#                                           ParaView's programs from
#                                           RAYSCOPE_PARAVIEW_ROOT (scripts/setup)
#
# `cmake --install` of the main build copies the plugin to
# <prefix>/lib/paraview-5.11/plugins/RayScope.
include(ExternalProject)

set(RAYSCOPE_PARAVIEW_ROOT "/opt/rayscope-paraview" CACHE PATH
  "Where scripts/setup unpacked ParaView 5.11 (paraview, paraview-dev, python3-paraview); / for a system-wide ParaView with its Python")
set(_pv_libdir "${RAYSCOPE_PARAVIEW_ROOT}/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}")
set(_pv_cmake_dir "${_pv_libdir}/cmake/paraview-5.11")
if(NOT EXISTS "${_pv_cmake_dir}/paraview-config.cmake")
  message(FATAL_ERROR "ParaView 5.11 not found in RAYSCOPE_PARAVIEW_ROOT=${RAYSCOPE_PARAVIEW_ROOT} "
    "(no ${_pv_cmake_dir}/paraview-config.cmake): run scripts/setup, or configure with "
    "-DRAYSCOPE_BUILD_PARAVIEW_PLUGIN=OFF")
endif()

set(_pv_dir "${CMAKE_BINARY_DIR}/paraview")
set(RAYSCOPE_PARAVIEW_PLUGIN_PATH "${_pv_dir}/install/lib/paraview-5.11/plugins/RayScope")
ExternalProject_Add(rayscope_paraview_plugin
  SOURCE_DIR  "${CMAKE_CURRENT_LIST_DIR}"
  BINARY_DIR  "${_pv_dir}/build"
  INSTALL_DIR "${_pv_dir}/install"
  CMAKE_ARGS
    "-DParaView_DIR=${_pv_cmake_dir}"
    "-DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}"
    "-DCMAKE_INSTALL_PREFIX=<INSTALL_DIR>"
    "-DCMAKE_C_COMPILER=${CMAKE_C_COMPILER}"
    "-DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}"
    "-DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}"
    "-DRAYSCOPE_NATIVE=${RAYSCOPE_NATIVE}"
  BUILD_BYPRODUCTS "${RAYSCOPE_PARAVIEW_PLUGIN_PATH}/RayScope.so")
# Rebuilt (incrementally) when a file it is built from changes: the core's,
# the mesh library's, the module's and the plugin's own sources, and the
# shared CMake settings (listed again when a file is added or removed).
file(GLOB_RECURSE _plugin_inputs CONFIGURE_DEPENDS
  "${PROJECT_SOURCE_DIR}/raytracer/*" "${PROJECT_SOURCE_DIR}/vtkplugin/*"
  "${PROJECT_SOURCE_DIR}/cmake/*")
ExternalProject_Add_StepDependencies(rayscope_paraview_plugin build ${_plugin_inputs})

# Launchers: ParaView's programs with the libraries and Python modules of
# RAYSCOPE_PARAVIEW_ROOT (its pvpython finds its Python modules next to the
# libraries it loaded).
foreach(program pvpython pvbatch pvserver paraview)
  set(_exe "${RAYSCOPE_PARAVIEW_ROOT}/usr/bin/${program}")
  if(program STREQUAL "pvpython" OR program STREQUAL "pvbatch")
    set(_exe "${_exe}3.11")  # the Debian names; pvpython/pvbatch are links to them
  endif()
  file(CONFIGURE OUTPUT "${_pv_dir}/${program}" @ONLY CONTENT [=[#!/bin/sh
# ParaView's @program@ from @RAYSCOPE_PARAVIEW_ROOT@ (written by CMake).
# Load RayScope's plugin with PV_PLUGIN_PATH=@RAYSCOPE_PARAVIEW_PLUGIN_PATH@
export LD_LIBRARY_PATH="@_pv_libdir@${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
exec "@_exe@" "$@"
]=])
  file(CHMOD "${_pv_dir}/${program}" PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
endforeach()
set(RAYSCOPE_PVPYTHON "${_pv_dir}/pvpython")
set(RAYSCOPE_PVBATCH "${_pv_dir}/pvbatch")
set(RAYSCOPE_PVSERVER "${_pv_dir}/pvserver")
set(RAYSCOPE_PARAVIEW "${_pv_dir}/paraview")

include(GNUInstallDirs)
install(DIRECTORY "${RAYSCOPE_PARAVIEW_PLUGIN_PATH}"
  DESTINATION "${CMAKE_INSTALL_LIBDIR}/paraview-5.11/plugins" COMPONENT paraview)

# What every RayScope CMake configuration shares: the C++ standard, the
# warning and optimisation flags of RayScope's own targets, and the packages
# the core (raytracer/) and rayscope_vtkio (vtkplugin/meshio) link to.
# Included by the top-level CMakeLists.txt and by the ParaView plugin's own
# configuration (vtkplugin/paraview), which builds the same core against
# ParaView's VTK.
set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

option(RAYSCOPE_NATIVE "Optimise for the build machine (-march=native)" ON)

# Warnings are an error budget of zero; applied to our targets only.
add_library(rayscope_warnings INTERFACE)
target_compile_options(rayscope_warnings INTERFACE -Wall -Wextra)
add_library(rayscope_opt INTERFACE)
# No fused multiply-add contraction: every instantiation of the templated tracer
# (plain, recording, counting) then rounds identically, which is what makes a
# replayed pixel bit-identical to the full render.
target_compile_options(rayscope_opt INTERFACE -ffp-contract=off)
if(RAYSCOPE_NATIVE)
  target_compile_options(rayscope_opt INTERFACE -march=native)
endif()

find_package(glm REQUIRED)
find_package(TBB REQUIRED)
# Debian's OpenImageIOConfig.cmake names OpenCV include paths that need not exist;
# the pkg-config file is enough for what RayScope uses.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
find_package(nlohmann_json REQUIRED)

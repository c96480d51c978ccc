# What every RayScope CMake configuration shares: the C++ standard, the
# warning, rounding and optimisation flags of RayScope's own targets, and the packages
# the core (raytracer/) and rayscope_vtkio (vtkplugin/vtkio) link to.
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

# Off by default: the build runs on every x86-64 CPU, and the hot loops pick
# the widest instructions the CPU has at run time (raytracer/include/rayscope/kernels.h).
option(RAYSCOPE_NATIVE "Compile everything for the build machine only (-march=native)" OFF)

# Warnings are an error budget of zero; applied to our targets only.
add_library(rayscope_warnings INTERFACE)
target_compile_options(rayscope_warnings INTERFACE -Wall -Wextra)
# Exact floating-point rounding: no fused multiply-add contraction, so that
# every instantiation of the templated tracer (plain, recording, counting)
# rounds identically, which is what makes a replayed pixel bit-identical to
# the full render. A correctness flag: the core's public headers hold those
# templates, so it is part of the core's interface (linked PUBLIC).
add_library(rayscope_fp_exact INTERFACE)
target_compile_options(rayscope_fp_exact INTERFACE -ffp-contract=off)
# Optimisation for the build machine: a directory option, so it applies to the
# targets of this configuration (RayScope's own) and never to a target that
# links them (an installed package's or the ParaView plugin's users).
if(RAYSCOPE_NATIVE)
  add_compile_options(-march=native)
endif()
# The x86-64 levels above the baseline that the hot loops are compiled for
# (raytracer/include/rayscope/isa.h, kernels.h), each as GCC's -march name;
# the tests compile some suites for them too.
set(RAYSCOPE_LEVEL_MARCH_sse42 x86-64-v2)
set(RAYSCOPE_LEVEL_MARCH_avx2 x86-64-v3)
set(RAYSCOPE_LEVEL_MARCH_avx512 x86-64-v4)

find_package(glm REQUIRED)
find_package(TBB REQUIRED)
# Debian's OpenImageIOConfig.cmake names OpenCV include paths that need not exist;
# the pkg-config file is enough for what RayScope uses.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)
find_package(nlohmann_json REQUIRED)

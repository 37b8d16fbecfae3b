# Every third-party dependency, found once, from Debian 12's packages
# (scripts/setup.sh installs them). Each is linked PRIVATE by the one target
# whose source file uses it.

find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)

# Embree 3: imported target `embree`.
find_package(embree 3 REQUIRED)

find_package(OpenEXR 3 REQUIRED)

# OpenImageIO's package config needs openimageio-tools installed, and Debian's
# imported target lists /usr/include/opencv4, which does not exist unless
# OpenCV's headers are installed: CMake's generate step then fails. Keep only
# the include directories that exist.
find_package(OpenImageIO REQUIRED)
foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
  if(dirs)
    set(kept "")
    foreach(d IN LISTS dirs)
      if(EXISTS "${d}")
        list(APPEND kept "${d}")
      endif()
    endforeach()
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${kept}")
  endif()
endforeach()

# CGAL is header-only; it warns about the build type unless told not to.
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL REQUIRED)

# tinygltf is a compiled library in Debian: never define TINYGLTF_IMPLEMENTATION.
find_package(TinyGLTF REQUIRED)

# MPI (Debian's Open MPI, libopenmpi-dev): only sim/distributed.cpp includes
# it. Without it (not found, or -DGONIO_MPI=OFF) gonio runs as one process.
# Its C API is all we use: skip the deprecated C++ bindings.
set(GONIO_WITH_MPI OFF)
if(GONIO_MPI)
  set(MPI_CXX_SKIP_MPICXX ON)
  find_package(MPI COMPONENTS CXX)
  if(MPI_CXX_FOUND)
    set(GONIO_WITH_MPI ON)
  else()
    message(STATUS "MPI not found: gonio builds without it (scripts/setup.sh installs libopenmpi-dev)")
  endif()
endif()
find_program(GONIO_MPIRUN NAMES mpirun mpiexec)

# cpp-httplib (the live page's server): Debian ships it compiled, with a
# pkg-config file whose flags (OpenSSL, zlib, brotli support) the header
# must see to match the library. Only tools/live/live_server.cpp includes it.
find_package(PkgConfig REQUIRED)
pkg_check_modules(httplib REQUIRED IMPORTED_TARGET cpp-httplib)

# pugixml (TM-33 and GLDF XML): imported target pugixml::pugixml.
find_package(pugixml REQUIRED)

# libzip (GLDF containers). Debian 12's libzip CMake package names the
# zipcmp/zipmerge/ziptool executables, which libzip-dev does not install, and
# find_package(libzip) fails on them: use its pkg-config file instead.
pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip)

# xxHash (io/support/content_hash.cpp), used header-only: the pkg-config file finds
# libxxhash-dev's header.
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)

# toml++ (the CAD sidecar, io/model/parts_file.cpp only): header only.
find_package(tomlplusplus 3 REQUIRED)

# NLopt (gonio optimize's methods, design/optimize.cpp only): libnlopt-cxx-dev
# (its C library's CMake package, target NLopt::nlopt; nlopt.hpp wraps it).
find_package(NLopt REQUIRED)

# pagmo2 (gonio optimize's CMA-ES, design/optimize_cmaes.cpp only):
# libpagmo-dev, its CMake package (target Pagmo::pagmo; it finds Boost,
# Eigen 3 and TBB itself).
find_package(pagmo REQUIRED)

# OpenCASCADE 7.6 (STEP and IGES, io/model/step.cpp only): linked by the
# helper program gonio-cad alone, never by gonio (~60 shared libraries at
# every start). Debian's config includes a module's targets only where its
# -dev package is installed, so the modules are named; its version file
# accepts only the exact version asked for (7.6 refuses 7.6.3), so the
# version is checked here. Without it (-DGONIO_OCCT=OFF, or not found) gonio
# refuses CAD files, saying so.
set(GONIO_WITH_OCCT OFF)
if(GONIO_OCCT)
  find_package(OpenCASCADE QUIET COMPONENTS FoundationClasses ModelingData ModelingAlgorithms
    Visualization ApplicationFramework DataExchange)
  if(OpenCASCADE_FOUND AND OpenCASCADE_VERSION VERSION_GREATER_EQUAL 7.6 AND TARGET TKXDESTEP
     AND TARGET TKXDEIGES AND TARGET TKMesh)
    set(GONIO_WITH_OCCT ON)
  else()
    message(STATUS "OpenCASCADE not found: gonio builds without STEP and IGES "
      "(scripts/setup.sh installs libocct-data-exchange-dev)")
  endif()
endif()

if(GONIO_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
if(GONIO_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

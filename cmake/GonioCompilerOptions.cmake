# Warnings, optimisation and sanitizer flags, as INTERFACE targets that every
# Gonio target links. Nothing here is global: third-party code keeps its flags.

add_library(gonio_warnings INTERFACE)
add_library(gonio::warnings ALIAS gonio_warnings)
target_compile_options(gonio_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wdouble-promotion
  -Wformat=2 -Wimplicit-fallthrough -Wmisleading-indentation
  -Werror=return-type -Werror=uninitialized)
# GCC 12 reports false -Wrestrict positives inside libstdc++'s std::string
# concatenation at -O3 (GCC bug 105329); -Wnull-dereference likewise inside
# std::vector growth, so it is not enabled.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(gonio_warnings INTERFACE -Wno-restrict)
endif()
# CI builds with GONIO_WERROR=ON (scripts/test.sh, when the environment sets
# GONIO_WERROR=1), so that a warning fails the build instead of scrolling by.
option(GONIO_WERROR "Treat compiler warnings in Gonio's own code as errors" OFF)
if(GONIO_WERROR)
  target_compile_options(gonio_warnings INTERFACE -Werror)
endif()

# Options for the hot numeric code: no -ffast-math (NaN checks must survive),
# but let the compiler contract multiply-adds and vectorise.
add_library(gonio_optimize INTERFACE)
add_library(gonio::optimize ALIAS gonio_optimize)
target_compile_options(gonio_optimize INTERFACE
  $<$<CONFIG:Release,RelWithDebInfo>:-O3 -fno-math-errno -ffp-contract=fast>
  # Position-independent code (CMakeLists.txt) without the cost of -fPIC:
  # no function of ours is ever interposed by another library's.
  -fno-semantic-interposition)

add_library(gonio_sanitize INTERFACE)
add_library(gonio::sanitize ALIAS gonio_sanitize)
if(GONIO_SANITIZE)
  target_compile_options(gonio_sanitize INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined
    -fno-omit-frame-pointer)
  target_link_options(gonio_sanitize INTERFACE -fsanitize=address,undefined)
endif()
# GONIO_FUZZ (tests/fuzz, scripts/fuzz.sh): clang's coverage instrumentation
# for libFuzzer on every Gonio target, with the same sanitizers.
if(GONIO_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "GONIO_FUZZ needs clang (scripts/fuzz.sh configures clang++-14)")
  endif()
  if(GONIO_SANITIZE)
    message(FATAL_ERROR "GONIO_FUZZ brings its own sanitizers; leave GONIO_SANITIZE off")
  endif()
  # The checkout's path mapped away in __FILE__ and the debug information
  # (scripts/fuzz.sh has ccache hand the compiler relative paths, which the
  # sanitizers' own metadata needs): the same code builds the same binary
  # in any clone, so that a run repeats wherever it is made.
  target_compile_options(gonio_sanitize INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
    -fno-omit-frame-pointer -g "-ffile-prefix-map=${PROJECT_SOURCE_DIR}/=")
  target_link_options(gonio_sanitize INTERFACE -fsanitize=address,undefined)
endif()

# The test programs' own files at -O1: the code they test is built -O3 (its
# libraries), while they themselves run little but set-ups and comparisons;
# at -O3 they were more than half the Release build's compile time
# (docs/validation.md, "Continuous integration"). Same floating-point flags.
add_library(gonio_optimize_tests INTERFACE)
target_compile_options(gonio_optimize_tests INTERFACE
  $<$<CONFIG:Release,RelWithDebInfo>:-O1 -fno-math-errno -ffp-contract=fast>
  -fno-semantic-interposition)

# One line per Gonio target: warnings, optimisation and sanitizers.
function(gonio_target_defaults target)
  target_link_libraries(${target} PRIVATE gonio::warnings gonio::optimize gonio::sanitize)
endfunction()

# The same for a test program's own files (-O1, above).
function(gonio_test_defaults target)
  target_link_libraries(${target} PRIVATE gonio::warnings gonio_optimize_tests gonio::sanitize)
endfunction()

# The layers of the source tree and what each may include, checked at build
# time: every library of a folder depends on that folder's check, so a quoted
# #include outside the folder's list fails the build, naming the file, the
# line and the folder's rule (cmake/check_includes.cmake does the reading).
#
#   gonio_layer(FOLDER io/photometric MAY_INCLUDE photometry io/support)
#
# FOLDER is relative to the source root; its own headers are always allowed,
# and so are the build's generated headers (gonio/...). An entry of
# MAY_INCLUDE names a folder (all its headers, not those of its subfolders)
# or one header (sim/scene.h). Only that folder's own files are read, not its
# subfolders'. System and third-party headers (<...>) are not the layers'
# business: each library's link line decides which it can find.
set(GONIO_LAYER_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/check_includes.cmake")

function(gonio_layer)
  cmake_parse_arguments(ARG "" "FOLDER" "MAY_INCLUDE" ${ARGN})
  string(REPLACE "/" "_" name "${ARG_FOLDER}")
  file(GLOB files CONFIGURE_DEPENDS LIST_DIRECTORIES false
    "${PROJECT_SOURCE_DIR}/${ARG_FOLDER}/*.h" "${PROJECT_SOURCE_DIR}/${ARG_FOLDER}/*.cpp")
  list(SORT files)
  set(stamp "${PROJECT_BINARY_DIR}/layers/${name}.checked")
  set(allowed ${ARG_FOLDER} ${ARG_MAY_INCLUDE} gonio)
  string(REPLACE ";" "," allowed "${allowed}")
  string(REPLACE ";" "," file_list "${files}")
  add_custom_command(
    OUTPUT "${stamp}"
    COMMAND ${CMAKE_COMMAND} "-DFOLDER=${ARG_FOLDER}" "-DALLOWED=${allowed}"
            "-DFILES=${file_list}" "-DROOT=${PROJECT_SOURCE_DIR}" "-DSTAMP=${stamp}"
            -P "${GONIO_LAYER_SCRIPT}"
    DEPENDS ${files} "${GONIO_LAYER_SCRIPT}"
    COMMENT "Checking what ${ARG_FOLDER}/ includes"
    VERBATIM)
  add_custom_target(gonio_layer_${name} DEPENDS "${stamp}")
  set_property(GLOBAL APPEND PROPERTY GONIO_LAYERS "${ARG_FOLDER}")
endfunction()

# Makes TARGET wait for its folder's check (call after gonio_layer in the
# same folder's CMakeLists.txt).
function(gonio_in_layer target folder)
  string(REPLACE "/" "_" name "${folder}")
  add_dependencies(${target} gonio_layer_${name})
endfunction()

# cmake -DNPM=... -DDIR=... -DVERSION=... -DSTAMP=... -P install_three.cmake
# Installs three@VERSION into DIR/node_modules with npm; a failure (no
# registry) is a warning, not a build error: the live page then has no 3D view.
execute_process(
  COMMAND "${NPM}" install --no-save --no-audit --no-fund --fetch-retries=1 --fetch-timeout=60000
          --prefix "${DIR}" "three@${VERSION}"
  RESULT_VARIABLE result OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  message(WARNING "npm could not install three@${VERSION} (the live page will have no 3D view): ${err}")
endif()
file(WRITE "${STAMP}" "three@${VERSION} npm exit ${result}\n")

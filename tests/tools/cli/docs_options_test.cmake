# Docs.OptionsMatchHelp: every subcommand's options in `gonio CMD --help` and
# in docs/commands/CMD.md are the same set, and every subcommand has a page.
#
#   cmake -DGONIO=path/to/gonio -DDOCS=docs/commands -P docs_options_test.cmake
#
# Options of the help are the entries of its "Options:" block ("  --name ARG",
# or "  -x, --name"); options of a page are the list items of its "## Options"
# section ("- `--name ARG` — text"). Fails (naming the command, the option and
# which side lacks it) when an option is added to the parser and not to the
# page, when a page keeps an option the parser no longer has, or when a
# subcommand has no page.
#
# With -DSELFTEST=1 it checks itself: on a copy of the pages with one option
# taken out of simulate.md, and on one with an invented option added to
# info.md, the check must fail and name that option.

cmake_minimum_required(VERSION 3.20)

if(NOT GONIO OR NOT DOCS)
  message(FATAL_ERROR "usage: cmake -DGONIO=gonio -DDOCS=docs/commands -P ${CMAKE_CURRENT_LIST_FILE}")
endif()

# Lines of a text as a CMake list; characters that CMake's list syntax would
# take as structure (';', '[', ']') are replaced: only option names matter.
function(text_lines text out)
  string(REPLACE ";" "," text "${text}")
  string(REPLACE "[" "(" text "${text}")
  string(REPLACE "]" ")" text "${text}")
  string(REPLACE "\\" "/" text "${text}")
  string(REPLACE "\n" ";" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# The names in one block of lines: from a line matching START to one matching
# STOP, the CMAKE_MATCH_<GROUP> of every line matching ENTRY.
function(block_names lines start stop entry group out)
  set(names "")
  set(inside FALSE)
  foreach(line IN LISTS lines)
    if(line MATCHES "${start}")
      set(inside TRUE)
    elseif(inside AND line MATCHES "${stop}")
      set(inside FALSE)
    elseif(inside AND line MATCHES "${entry}")
      list(APPEND names "${CMAKE_MATCH_${group}}")
    endif()
  endforeach()
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

if(SELFTEST)
  set(work "${WORK}")
  if(NOT work)
    set(work "${CMAKE_CURRENT_BINARY_DIR}/docs-options-selftest")
  endif()
  foreach(case missing extra)
    file(REMOVE_RECURSE "${work}/${case}")
    file(COPY "${DOCS}/" DESTINATION "${work}/${case}")
  endforeach()
  # (1) one option taken out of a page: the parser has it, the page not.
  file(READ "${work}/missing/simulate.md" page)
  string(REGEX REPLACE "\n- `--seed [^\n]*" "" cut "${page}")
  if(cut STREQUAL page)
    message(FATAL_ERROR "self-test: simulate.md lists no --seed to take out")
  endif()
  file(WRITE "${work}/missing/simulate.md" "${cut}")
  # (2) an option the parser does not have, added to a page.
  file(READ "${work}/extra/info.md" page)
  string(REPLACE "\n## Options\n" "\n## Options\n\n- `--no-such-option` — invented by the self-test\n" added "${page}")
  file(WRITE "${work}/extra/info.md" "${added}")
  foreach(case missing extra)
    execute_process(COMMAND "${CMAKE_COMMAND}" "-DGONIO=${GONIO}" "-DDOCS=${work}/${case}"
                            -P "${CMAKE_CURRENT_LIST_FILE}"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc EQUAL 0)
      message(FATAL_ERROR "self-test (${case}): the check passed on doctored pages")
    endif()
    if(case STREQUAL "missing")
      set(want "simulate: --seed is in `gonio simulate --help` but not in")
    else()
      set(want "info: --no-such-option is in")
    endif()
    string(FIND "${out}${err}" "${want}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "self-test (${case}): the failure does not say '${want}':\n${out}${err}")
    endif()
  endforeach()
  message(STATUS "self-test: a page without --seed and a page with an invented option both fail")
  return()
endif()

execute_process(COMMAND "${GONIO}" --help RESULT_VARIABLE rc OUTPUT_VARIABLE top)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${GONIO} --help exited ${rc}")
endif()
text_lines("${top}" top_lines)
block_names("${top_lines}" "^Commands:" "^[^ ]" "^  ([a-z0-9-]+)  " 1 commands)
list(LENGTH commands n)
if(n LESS 5)
  message(FATAL_ERROR "found only ${n} subcommands in `gonio --help`: '${commands}'")
endif()

set(problems "")
foreach(cmd IN LISTS commands)
  execute_process(COMMAND "${GONIO}" ${cmd} --help RESULT_VARIABLE rc OUTPUT_VARIABLE help)
  if(NOT rc EQUAL 0)
    string(APPEND problems "${cmd}: `gonio ${cmd} --help` exited ${rc}\n")
    continue()
  endif()
  text_lines("${help}" help_lines)
  block_names("${help_lines}" "^Options:" "^[^ ]"
              "^  (-[A-Za-z0-9], )?(--[A-Za-z0-9][A-Za-z0-9-]*)" 2 help_opts)
  if(NOT help_opts)
    string(APPEND problems "${cmd}: no options found in `gonio ${cmd} --help`\n")
  endif()

  set(page "${DOCS}/${cmd}.md")
  if(NOT EXISTS "${page}")
    string(APPEND problems "${cmd}: no page ${page}\n")
    continue()
  endif()
  file(READ "${page}" text)
  text_lines("${text}" page_lines)
  block_names("${page_lines}" "^## Options" "^## "
              "^- `(-[A-Za-z0-9], )?(--[A-Za-z0-9][A-Za-z0-9-]*)" 2 page_opts)

  foreach(opt IN LISTS help_opts)
    if(NOT opt IN_LIST page_opts)
      string(APPEND problems "${cmd}: ${opt} is in `gonio ${cmd} --help` but not in ${page}'s ## Options\n")
    endif()
  endforeach()
  foreach(opt IN LISTS page_opts)
    if(NOT opt IN_LIST help_opts)
      string(APPEND problems "${cmd}: ${opt} is in ${page}'s ## Options but not in `gonio ${cmd} --help`\n")
    endif()
  endforeach()
  list(LENGTH help_opts nh)
  list(LENGTH page_opts np)
  message(STATUS "${cmd}: ${nh} options in --help, ${np} on ${page}")
endforeach()

# A page for a subcommand that no longer exists.
file(GLOB pages RELATIVE "${DOCS}" "${DOCS}/*.md")
foreach(p IN LISTS pages)
  string(REGEX REPLACE "\\.md$" "" name "${p}")
  if(NOT name STREQUAL "README" AND NOT name IN_LIST commands)
    string(APPEND problems "${name}: ${DOCS}/${p} documents no subcommand of `gonio --help`\n")
  endif()
endforeach()

if(problems)
  message(FATAL_ERROR "docs/commands and --help disagree:\n${problems}")
endif()

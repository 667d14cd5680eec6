# The shared core serves both hosts, so it must not see either host's private headers: fails when a
# file under base_radiosity/shared includes a header of the BRIGHT-like host (base_radiosity/bright,
# public include/ or private src/) or of the VISION-like host (vision_host/). The compiler would
# catch most (hr_shared's include path has neither), but not a quoted include of a file that a
# relative path reaches, and not before the build: this names the file and line at configure time.
# Run at configure time from base_radiosity/CMakeLists.txt and as the test shared_core_includes:
#   cmake -DROOT=<source dir> -P check_shared_includes.cmake
cmake_minimum_required(VERSION 3.25)
set(private "")       # as included through an include path: hr/solver.h, vision/solver.h
set(private_src "")   # a host's src/ headers, by name: solver_state.h, state.h
foreach(dir ${ROOT}/base_radiosity/bright/include ${ROOT}/vision_host/include)
  file(GLOB_RECURSE hs RELATIVE ${dir} ${dir}/*.h)
  list(APPEND private ${hs})
endforeach()
foreach(dir ${ROOT}/base_radiosity/bright/src ${ROOT}/vision_host/src)
  file(GLOB_RECURSE hs RELATIVE ${dir} ${dir}/*.h)
  list(APPEND private_src ${hs})
endforeach()
list(APPEND private ${private_src})
list(LENGTH private nprivate)
if(nprivate EQUAL 0)
  message(FATAL_ERROR "no host-private headers found under ${ROOT}: the check would pass vacuously")
endif()

file(GLOB_RECURSE shared ${ROOT}/base_radiosity/shared/*.h ${ROOT}/base_radiosity/shared/*.cpp
     ${ROOT}/base_radiosity/shared/*.in)
list(LENGTH shared nshared)
if(nshared EQUAL 0)
  message(FATAL_ERROR "no shared sources found under ${ROOT}/base_radiosity/shared")
endif()
set(found "")
foreach(f IN LISTS shared)
  get_filename_component(here ${f} DIRECTORY)
  # Only the include lines: whole C++ lines would not survive as a CMake list (brackets, semicolons).
  file(STRINGS ${f} lines REGEX "^[ \t]*#[ \t]*include")
  foreach(l IN LISTS lines)
    if(l MATCHES "^[ \t]*#[ \t]*include[ \t]*([<\"])([^>\"]+)[>\"]")
      set(quote "${CMAKE_MATCH_1}")
      set(inc "${CMAKE_MATCH_2}")
      set(bad FALSE)
      get_filename_component(abs ${here}/${inc} ABSOLUTE)
      if(quote STREQUAL "\"" AND EXISTS ${abs})
        # A quoted include found beside the includer: fine while it stays inside shared/.
        string(FIND "${abs}/" "${ROOT}/base_radiosity/shared/" at)
        if(NOT at EQUAL 0)
          set(bad TRUE)
        endif()
      elseif(inc IN_LIST private)
        set(bad TRUE)
      endif()
      if(bad)
        file(RELATIVE_PATH rel ${ROOT} ${f})
        if(quote STREQUAL "<")
          list(APPEND found "${rel}: #include <${inc}>")
        else()
          list(APPEND found "${rel}: #include \"${inc}\"")
        endif()
      endif()
    endif()
  endforeach()
endforeach()
include(${ROOT}/cmake/source_check.cmake)
ghr_source_check_verdict("${found}" "the shared core includes host-private headers"
  "shared core: ${nshared} files, none includes any of the hosts' ${nprivate} private header names")

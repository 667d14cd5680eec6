# Fails when a host's source names the glossy extension: its namespace or include folder
# ("glossy"), its algorithm ("Illumination Samples", "IlluminationSamples") or its library target.
# Checked: vision_host/ (all of it). Not yet: base_radiosity/bright, whose comments and one
# variable still say "glossy" (solver_state.cpp, refine.cpp, push_pull.cpp, shoot.cpp), and
# base_radiosity/shared, where the word is the program's name "glossyhr" or Material::glossy().
# Run: cmake -DROOT=<source dir> -P no_extension_names.cmake
set(patterns "glossy" "illumination.?samples" "glossy_extension")
file(GLOB_RECURSE sources ${ROOT}/vision_host/*.h ${ROOT}/vision_host/*.cpp ${ROOT}/vision_host/CMakeLists.txt)
set(found "")
foreach(f IN LISTS sources)
  file(READ ${f} text)
  string(TOLOWER "${text}" text)
  foreach(p IN LISTS patterns)
    if(text MATCHES "${p}")
      list(APPEND found "${f}: ${p}")
    endif()
  endforeach()
endforeach()
list(LENGTH sources n)
if(n EQUAL 0)
  message(FATAL_ERROR "no host sources found under ${ROOT}/vision_host")
endif()
include(${ROOT}/cmake/source_check.cmake)
ghr_source_check_verdict("${found}" "host sources name the extension" "${n} host source files, none names the extension")

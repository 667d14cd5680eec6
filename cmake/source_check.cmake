# The verdict of a source check run as a script (cmake -P): fails listing what it found, one item a
# line, or says what passed. Shared by the checks that read sources: base_radiosity/
# check_shared_includes.cmake and tests/vision/no_extension_names.cmake.
function(ghr_source_check_verdict found failure passed)
  if(found)
    string(REPLACE ";" "\n  " found "${found}")
    message(FATAL_ERROR "${failure}:\n  ${found}")
  endif()
  message(STATUS "${passed}")
endfunction()

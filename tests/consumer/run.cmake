# ctest driver: install the build tree into WORK_DIR/prefix, then build and run the consumer against it, and the
# README's C++ example exactly as the README writes it (its ```cpp block), from the repository root.
file(REMOVE_RECURSE ${WORK_DIR})
file(READ ${README} readme)
string(FIND "${readme}" "```cpp\n" begin)
if(begin EQUAL -1)
  message(FATAL_ERROR "${README} has no ```cpp block")
endif()
math(EXPR begin "${begin} + 7")
string(SUBSTRING "${readme}" ${begin} -1 example)
string(FIND "${example}" "```" end)
string(SUBSTRING "${example}" 0 ${end} example)
file(WRITE ${WORK_DIR}/readme_example.cc "${example}")
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${WORK_DIR}/prefix"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR};-B;${WORK_DIR}/build;-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix;-DCMAKE_BUILD_TYPE=Release;-DREADME_EXAMPLE=${WORK_DIR}/readme_example.cc"
    "${CMAKE_COMMAND};--build;${WORK_DIR}/build"
    "${WORK_DIR}/build/consumer"
    "${WORK_DIR}/build/readme_example")
  execute_process(COMMAND ${step} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err
                  WORKING_DIRECTORY ${REPOSITORY})
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "consumer step failed: ${step}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endforeach()

# cmake -DBUILD=<build tree> -DPREFIX=<folder> -P install_prefix.cmake:
# a fresh `cmake --install` of the build into PREFIX (the set-up step of
# the install tests).
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${PREFIX} OUTPUT_QUIET
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD} --prefix ${PREFIX} failed (${rc}): is everything built?")
endif()

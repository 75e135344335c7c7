# FlatBuffers at build time: flatc generates C++ headers from schemas and
# compiles JSON documents (node configs) to binary. The runtime headers are
# header-only, so one copy serves the host and every cross target.

find_program(TROUPE_FLATC flatc REQUIRED NO_CMAKE_FIND_ROOT_PATH)
find_path(TROUPE_FLATBUFFERS_HEADERS flatbuffers/flatbuffers.h REQUIRED NO_CMAKE_FIND_ROOT_PATH)

set(TROUPE_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
file(MAKE_DIRECTORY ${TROUPE_GENERATED_DIR})

# Cross builds must not see the host's /usr/include, so the FlatBuffers headers
# are exposed through a folder of their own.
set(TROUPE_FLATBUFFERS_INCLUDE ${PROJECT_BINARY_DIR}/flatbuffers-include)
file(MAKE_DIRECTORY ${TROUPE_FLATBUFFERS_INCLUDE})
file(CREATE_LINK ${TROUPE_FLATBUFFERS_HEADERS}/flatbuffers
     ${TROUPE_FLATBUFFERS_INCLUDE}/flatbuffers SYMBOLIC)

# troupe_flatc_cpp(<out-var> OUTPUT_DIR <dir> SCHEMAS <fbs...> [INCLUDES <dirs...>])
# Generates <name>_generated.h for every schema into OUTPUT_DIR and puts the
# header paths into <out-var>.
function(troupe_flatc_cpp out_var)
  cmake_parse_arguments(ARG "" "OUTPUT_DIR" "SCHEMAS;INCLUDES" ${ARGN})
  set(include_flags "")
  foreach(dir ${ARG_INCLUDES})
    list(APPEND include_flags -I ${dir})
  endforeach()
  set(headers "")
  foreach(schema ${ARG_SCHEMAS})
    get_filename_component(name ${schema} NAME_WE)
    set(header ${ARG_OUTPUT_DIR}/${name}_generated.h)
    add_custom_command(
      OUTPUT ${header}
      COMMAND ${TROUPE_FLATC} --cpp --scoped-enums --cpp-std c++17 ${include_flags}
              -o ${ARG_OUTPUT_DIR} ${schema}
      DEPENDS ${schema} ${ARG_SCHEMAS}
      COMMENT "flatc ${name}.fbs"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  set(${out_var} ${headers} PARENT_SCOPE)
endfunction()

# troupe_embed(<out-cc> SYMBOL <name> INPUT <file>)
# Writes a .cc that defines `extern const unsigned char <name>[]` and
# `extern const unsigned <name>_size` holding the bytes of INPUT.
function(troupe_embed out_cc)
  cmake_parse_arguments(ARG "" "SYMBOL;INPUT" "" ${ARGN})
  add_custom_command(
    OUTPUT ${out_cc}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${ARG_INPUT} -DOUTPUT=${out_cc} -DSYMBOL=${ARG_SYMBOL}
            -P ${PROJECT_SOURCE_DIR}/wire/embed.cmake
    DEPENDS ${ARG_INPUT} ${PROJECT_SOURCE_DIR}/wire/embed.cmake
    COMMENT "embed ${ARG_SYMBOL}"
    VERBATIM)
endfunction()

# Turns the ROS 2 message definitions of this folder (<package>/<Type>.msg,
# ROS 2's .msg syntax) into what the bridge and its tests build on:
#
#   OUT_IDL     one IDL file with every type under its DDS name, as ROS 2
#               names them (module sensor_msgs::msg::dds_, struct LaserScan_),
#               for Cyclone's idlc and Fast DDS's fastddsgen;
#   OUT_HEADER  a C++ table: each type's ROS name, DDS name and RIHS01 type
#               hash (the SHA-256 of its canonical type description, which
#               ROS 2 Iron and later put in every endpoint's user data).
#
#   cmake -DMSG_DIR=... -DOUT_IDL=... -DOUT_HEADER=... -P ros2_types.cmake
#
# Only what these definitions use is supported: primitive types, strings
# (bounded or not), nested types, fixed arrays, bounded and unbounded
# sequences, constants. Anything else stops the build naming file and line.

cmake_minimum_required(VERSION 3.22)

# ROS primitive type -> IDL type and type_description_interfaces/FieldType id.
# (char is uint8 in ROS 2; byte is an octet.)
set(_idl_bool boolean)
set(_id_bool 15)
set(_idl_byte octet)
set(_id_byte 16)
set(_idl_char uint8)
set(_id_char 3)
set(_idl_int8 int8)
set(_id_int8 2)
set(_idl_uint8 uint8)
set(_id_uint8 3)
set(_idl_int16 int16)
set(_id_int16 4)
set(_idl_uint16 uint16)
set(_id_uint16 5)
set(_idl_int32 int32)
set(_id_int32 6)
set(_idl_uint32 uint32)
set(_id_uint32 7)
set(_idl_int64 int64)
set(_id_int64 8)
set(_idl_uint64 uint64)
set(_id_uint64 9)
set(_idl_float32 float)
set(_id_float32 10)
set(_idl_float64 double)
set(_id_float64 11)
set(_idl_string string)
set(_id_string 17)
set(_id_nested 1)
set(_id_bounded_string 21)
# Array kinds add to the element's id.
set(_add_array 48)
set(_add_bounded_sequence 96)
set(_add_sequence 144)

function(fail where what)
  message(FATAL_ERROR "${where}: ${what}")
endfunction()

# Parses <pkg>/<Type>.msg into variables named after "<pkg>/<Type>":
#   <T>_FIELDS  list of field indices; <T>_F<i>_{NAME,BASE,NESTED,ARRAY,CAP,STRCAP}
#   <T>_CONSTS  list of "type name value" entries
#   <T>_DEPS    nested types, "pkg/Type"
function(parse_msg type)
  string(REPLACE "/" ";" parts ${type})
  list(GET parts 0 pkg)
  set(path ${MSG_DIR}/${type}.msg)
  if(NOT EXISTS ${path})
    fail("${path}" "no such message definition")
  endif()
  file(STRINGS ${path} lines)
  set(fields "")
  set(consts "")
  set(deps "")
  set(n 0)
  set(line_no 0)
  foreach(line IN LISTS lines)
    math(EXPR line_no "${line_no} + 1")
    string(REGEX REPLACE "#.*$" "" line "${line}")
    string(STRIP "${line}" line)
    if(line STREQUAL "")
      continue()
    endif()
    set(where "${path}:${line_no}")
    if(line MATCHES "^([a-z0-9]+) +([A-Z][A-Z0-9_]*) *= *(.+)$")
      list(APPEND consts "${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ${CMAKE_MATCH_3}")
      continue()
    endif()
    # type[array] name [default]
    if(NOT line MATCHES "^([A-Za-z0-9_/]+)(<=([0-9]+))?(\\[(<=)?([0-9]*)\\])? +([a-z][a-z0-9_]*)( +.*)?$")
      fail("${where}" "cannot read '${line}'")
    endif()
    set(base ${CMAKE_MATCH_1})
    set(strcap "${CMAKE_MATCH_3}")
    set(has_array "${CMAKE_MATCH_4}")
    set(bounded "${CMAKE_MATCH_5}")
    set(cap "${CMAKE_MATCH_6}")
    set(name ${CMAKE_MATCH_7})
    set(nested "")
    if(NOT DEFINED _idl_${base})
      # A nested type: "pkg/Type", or "Type" of this package.
      if(base MATCHES "^([a-z0-9_]+)/([A-Z][A-Za-z0-9]*)$")
        set(nested ${base})
      elseif(base MATCHES "^[A-Z][A-Za-z0-9]*$")
        set(nested ${pkg}/${base})
      else()
        fail("${where}" "unknown type '${base}'")
      endif()
      list(APPEND deps ${nested})
    endif()
    if(NOT strcap STREQUAL "" AND NOT base STREQUAL "string")
      fail("${where}" "only strings take a bound")
    endif()
    if(NOT has_array)
      set(array none)
      set(cap 0)
    elseif(bounded)
      set(array bounded_sequence)
    elseif(cap STREQUAL "")
      set(array sequence)
      set(cap 0)
    else()
      set(array array)
    endif()
    if(strcap STREQUAL "")
      set(strcap 0)
    endif()
    set(${type}_F${n}_NAME ${name} PARENT_SCOPE)
    set(${type}_F${n}_BASE ${base} PARENT_SCOPE)
    set(${type}_F${n}_NESTED "${nested}" PARENT_SCOPE)
    set(${type}_F${n}_ARRAY ${array} PARENT_SCOPE)
    set(${type}_F${n}_CAP ${cap} PARENT_SCOPE)
    set(${type}_F${n}_STRCAP ${strcap} PARENT_SCOPE)
    list(APPEND fields ${n})
    math(EXPR n "${n} + 1")
  endforeach()
  if(n EQUAL 0)
    fail("${path}" "no fields")
  endif()
  list(REMOVE_DUPLICATES deps)
  set(${type}_FIELDS ${fields} PARENT_SCOPE)
  set(${type}_CONSTS "${consts}" PARENT_SCOPE)
  set(${type}_DEPS "${deps}" PARENT_SCOPE)
endfunction()

# "pkg/Type" -> "pkg/msg/Type" and "pkg::msg::dds_::Type_".
function(ros_names type ros_out dds_out)
  string(REPLACE "/" ";" parts ${type})
  list(GET parts 0 pkg)
  list(GET parts 1 name)
  set(${ros_out} "${pkg}/msg/${name}" PARENT_SCOPE)
  set(${dds_out} "${pkg}::msg::dds_::${name}_" PARENT_SCOPE)
endfunction()

# The canonical JSON of one type's description (type_description_interfaces'
# IndividualTypeDescription, default values left out), as ROS 2 hashes it.
function(type_json type out)
  ros_names(${type} ros dds)
  set(json "{\"type_name\": \"${ros}\", \"fields\": [")
  set(sep "")
  foreach(i IN LISTS ${type}_FIELDS)
    set(base ${${type}_F${i}_BASE})
    set(nested "${${type}_F${i}_NESTED}")
    set(strcap ${${type}_F${i}_STRCAP})
    set(nested_name "")
    if(NOT nested STREQUAL "")
      set(id ${_id_nested})
      ros_names(${nested} nested_name unused)
    elseif(base STREQUAL "string" AND NOT strcap EQUAL 0)
      set(id ${_id_bounded_string})
    else()
      set(id ${_id_${base}})
    endif()
    set(array ${${type}_F${i}_ARRAY})
    if(NOT array STREQUAL "none")
      math(EXPR id "${id} + ${_add_${array}}")
    endif()
    string(APPEND json "${sep}{\"name\": \"${${type}_F${i}_NAME}\", \"type\": {\"type_id\": ${id}, "
           "\"capacity\": ${${type}_F${i}_CAP}, \"string_capacity\": ${strcap}, "
           "\"nested_type_name\": \"${nested_name}\"}}")
    set(sep ", ")
  endforeach()
  string(APPEND json "]}")
  set(${out} "${json}" PARENT_SCOPE)
endfunction()

# Every type `type` refers to, directly or not.
function(closure type out)
  set(todo ${${type}_DEPS})
  set(all "")
  while(todo)
    list(POP_FRONT todo t)
    list(FIND all ${t} seen)
    if(seen EQUAL -1)
      list(APPEND all ${t})
      list(APPEND todo ${${t}_DEPS})
    endif()
  endwhile()
  set(${out} "${all}" PARENT_SCOPE)
endfunction()

function(type_hash type out)
  type_json(${type} main)
  closure(${type} refs)
  # Referenced descriptions sorted by their ROS names.
  set(keyed "")
  foreach(r IN LISTS refs)
    ros_names(${r} rname unused)
    list(APPEND keyed "${rname} ${r}")
  endforeach()
  list(SORT keyed)
  set(ref_json "")
  set(sep "")
  foreach(k IN LISTS keyed)
    string(REGEX REPLACE "^[^ ]* " "" r "${k}")
    type_json(${r} j)
    string(APPEND ref_json "${sep}${j}")
    set(sep ", ")
  endforeach()
  set(doc "{\"type_description\": ${main}, \"referenced_type_descriptions\": [${ref_json}]}")
  string(SHA256 digest "${doc}")
  set(${out} "RIHS01_${digest}" PARENT_SCOPE)
endfunction()

# ---- main ---------------------------------------------------------------------

foreach(v MSG_DIR OUT_IDL OUT_HEADER)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "ros2_types.cmake needs -D${v}=...")
  endif()
endforeach()

file(GLOB_RECURSE msg_files RELATIVE ${MSG_DIR} ${MSG_DIR}/*.msg)
list(SORT msg_files)
set(types "")
foreach(f IN LISTS msg_files)
  string(REGEX REPLACE "\\.msg$" "" t ${f})
  parse_msg(${t})
  list(APPEND types ${t})
endforeach()
foreach(t IN LISTS types)
  foreach(dep IN LISTS ${t}_DEPS)
    if(NOT dep IN_LIST types)
      fail("${MSG_DIR}/${t}.msg" "uses ${dep}, which has no definition here")
    endif()
  endforeach()
endforeach()

# Dependencies first (IDL needs a type declared before its use).
set(ORDER "")
set(todo ${types})
while(todo)
  set(progress OFF)
  foreach(t IN LISTS todo)
    set(ready ON)
    foreach(dep IN LISTS ${t}_DEPS)
      if(NOT dep IN_LIST ORDER)
        set(ready OFF)
      endif()
    endforeach()
    if(ready)
      list(APPEND ORDER ${t})
      list(REMOVE_ITEM todo ${t})
      set(progress ON)
    endif()
  endforeach()
  if(NOT progress)
    fail("${MSG_DIR}" "the types ${todo} refer to each other in a cycle")
  endif()
endwhile()

string(CONCAT idl "// Generated from drivers/ros2/msg by ros2_types.cmake; do not edit.\n"
       "// ROS 2 message types under their DDS names (plain CDR, final extensibility).\n")
set(table "")
foreach(t IN LISTS ORDER)
  string(REPLACE "/" ";" parts ${t})
  list(GET parts 0 pkg)
  list(GET parts 1 name)
  string(APPEND idl "\nmodule ${pkg} { module msg { module dds_ {\n")
  if(${t}_CONSTS)
    string(APPEND idl "module ${name}_Constants {\n")
    foreach(c IN LISTS ${t}_CONSTS)
      string(REPLACE " " ";" c ${c})
      list(GET c 0 ctype)
      list(GET c 1 cname)
      list(GET c 2 cvalue)
      string(APPEND idl "  const ${_idl_${ctype}} ${cname} = ${cvalue};\n")
    endforeach()
    string(APPEND idl "};\n")
  endif()
  string(APPEND idl "@final struct ${name}_ {\n")
  foreach(i IN LISTS ${t}_FIELDS)
    set(nested "${${t}_F${i}_NESTED}")
    if(nested STREQUAL "")
      set(ftype ${_idl_${${t}_F${i}_BASE}})
      if(NOT ${t}_F${i}_STRCAP EQUAL 0)
        set(ftype "string<${${t}_F${i}_STRCAP}>")
      endif()
    else()
      ros_names(${nested} unused ftype)
    endif()
    set(fname ${${t}_F${i}_NAME})
    set(cap ${${t}_F${i}_CAP})
    set(array ${${t}_F${i}_ARRAY})
    if(array STREQUAL "array")
      string(APPEND idl "  ${ftype} ${fname}[${cap}];\n")
    elseif(array STREQUAL "sequence")
      string(APPEND idl "  sequence<${ftype}> ${fname};\n")
    elseif(array STREQUAL "bounded_sequence")
      string(APPEND idl "  sequence<${ftype}, ${cap}> ${fname};\n")
    else()
      string(APPEND idl "  ${ftype} ${fname};\n")
    endif()
  endforeach()
  string(APPEND idl "};\n}; }; };\n")
  ros_names(${t} ros dds)
  type_hash(${t} hash)
  string(APPEND table "    {\"${ros}\", \"${dds}\", \"${hash}\"},\n")
endforeach()

set(header "// Generated from drivers/ros2/msg by ros2_types.cmake; do not edit.
#pragma once

#include <string_view>

namespace troupe::drivers::ros2 {

/// A ROS 2 message type the bridge knows.
struct RosTypeInfo {
  /// \"sensor_msgs/msg/LaserScan\"
  const char* ros_name;
  /// \"sensor_msgs::msg::dds_::LaserScan_\", the DDS type name ROS 2 uses
  const char* dds_name;
  /// \"RIHS01_\" and the hex SHA-256 of the type description (ROS 2 Iron+)
  const char* hash;
};

inline constexpr RosTypeInfo kRosTypes[] = {
${table}};

/// The entry for a DDS type name; nullptr when the bridge does not know it.
inline const RosTypeInfo* find_ros_type(std::string_view dds_name) {
  for (const RosTypeInfo& t : kRosTypes) {
    if (dds_name == t.dds_name) return &t;
  }
  return nullptr;
}

}  // namespace troupe::drivers::ros2
")

# Write only on change, so that what depends on the files is not rebuilt.
file(CONFIGURE OUTPUT ${OUT_IDL} CONTENT "${idl}" @ONLY)
file(CONFIGURE OUTPUT ${OUT_HEADER} CONTENT "${header}" @ONLY)

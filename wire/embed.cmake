# cmake -DINPUT=file -DOUTPUT=file.cc -DSYMBOL=name -P embed.cmake
file(READ ${INPUT} hex HEX)
string(LENGTH "${hex}" hex_len)
math(EXPR size "${hex_len} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "((0x..,){16})" "\\1\n" bytes "${bytes}")
file(WRITE ${OUTPUT}
  "// Generated from ${INPUT}; do not edit.\n"
  "// Aligned: FlatBuffers read 8-byte scalars in place (ARM faults on some unaligned loads).\n"
  "alignas(16) extern const unsigned char ${SYMBOL}[] = {\n${bytes}0};\n"
  "extern const unsigned ${SYMBOL}_size = ${size};\n")

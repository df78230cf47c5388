# Turns IN (any file) into OUT, a C source defining `const char NAME[]` (NUL-terminated) and
# `const size_t NAME_size` (without the NUL). Run with cmake -P.
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" n)
math(EXPR size "${n} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n" bytes "${bytes}")
file(WRITE ${OUT} "/* Generated from ${IN} by embed_file.cmake. */\n#include <stddef.h>\n\n"
	"const char ${NAME}[] = {\n${bytes}0x00\n};\nconst size_t ${NAME}_size = ${size};\n")

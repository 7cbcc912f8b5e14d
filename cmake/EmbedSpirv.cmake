# Turns a SPIR-V binary into a C++ array of 32-bit words (little-endian host assumed, as SPIR-V itself is).
file(READ ${INPUT} hex HEX)
string(LENGTH "${hex}" hex_len)
math(EXPR words "${hex_len} / 8")
string(REGEX REPLACE "([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])" "0x\\4\\3\\2\\1u," body "${hex}")
file(WRITE ${OUTPUT} "#include <cstddef>\n#include <cstdint>\nextern const std::uint32_t ${SYMBOL}[] = {${body}};\nextern const std::size_t ${SYMBOL}_words = ${words};\n")

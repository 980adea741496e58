# cmake -DIN=FILE -DOUT=HEADER -DNAME=SYMBOL -P embed_text.cmake
# Writes HEADER with FILE's text as `static const char SYMBOL[]`, so that a page or script
# can be kept and edited as the file it is and still ship inside the binary.
file(READ "${IN}" text)
set(delimiter "wmra_embed")
string(FIND "${text}" ")${delimiter}\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw-string delimiter )${delimiter}\"")
endif()
file(WRITE "${OUT}" "// generated from ${IN} by cmake/embed_text.cmake; do not edit\n#pragma once\n\nstatic const char ${NAME}[] = R\"${delimiter}(${text})${delimiter}\";\n")

# cmake -DIN=page.html -DOUT=view_page.hpp -P embed_page.cmake: the page as a C++ raw string constant, kPage.
file(READ ${IN} page)
string(FIND "${page}" ")estview_page\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${IN} contains the raw string's closing delimiter")
endif()
file(WRITE ${OUT} "#pragma once\n// Generated from ${IN} by embed_page.cmake: do not edit.\n"
                  "namespace view {\ninline constexpr char kPage[] = R\"estview_page(${page})estview_page\";\n}\n")

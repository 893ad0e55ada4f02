# camplace_embed_page(<page.html> <template.cpp.in> <output.cpp> <variable>): compiles a web page
# into a library (the programs must not depend on the source tree at run time). The page's line
# /*CAMPLACE_PAGE_COMMON*/ becomes view/assets/page_common.js, the error reporting and 3-D frame
# the export viewer and the serve planner share; the template gets the page as @<variable>@.
# CMake configures again when the page or the shared script changes.
function(camplace_embed_page page template output variable)
  set(common ${PROJECT_SOURCE_DIR}/view/assets/page_common.js)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${page} ${common})
  file(READ ${page} text)
  file(READ ${common} common_text)
  string(FIND "${text}" "/*CAMPLACE_PAGE_COMMON*/\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${page}: has no line /*CAMPLACE_PAGE_COMMON*/ for ${common}")
  endif()
  string(REPLACE "/*CAMPLACE_PAGE_COMMON*/\n" "${common_text}" text "${text}")
  set(${variable} "${text}")
  configure_file(${template} ${output} @ONLY)
endfunction()

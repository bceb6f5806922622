# quiver_embed_files(<out.cc> NAMESPACE <ns> HEADER <header> FILES <file>...): generates <out.cc>
# at build time, defining <ns>::embedded_file(name) (declared in <header>) over the files' contents,
# so that agents find their grammars and worlds wherever they run. Rebuilt when a file changes.
set(QUIVER_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_files.cmake)
function(quiver_embed_files out)
  cmake_parse_arguments(E "" "NAMESPACE;HEADER;COMMENT" "FILES" ${ARGN})
  string(REPLACE ";" "," list "${E_FILES}")
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DFILES=${list} -DNAMESPACE=${E_NAMESPACE} -DHEADER=${E_HEADER}
            -P ${QUIVER_EMBED_SCRIPT}
    VERBATIM
    DEPENDS ${E_FILES} ${QUIVER_EMBED_SCRIPT}
    COMMENT "${E_COMMENT}")
endfunction()

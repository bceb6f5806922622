# Script mode (cmake -P), run by quiver_embed_files(): writes OUT, a C++ file whose
# NAMESPACE::embedded_file(name) returns the contents of each of FILES (comma-separated) by file
# name, or an empty view. HEADER is the header declaring embedded_file.
set(body "#include <string_view>\n#include \"${HEADER}\"\nnamespace ${NAMESPACE} {\nnamespace {\nstruct File { std::string_view name, text; };\nconstexpr File kFiles[] = {\n")
string(REPLACE "," ";" FILES "${FILES}")
foreach(f ${FILES})
  file(READ ${f} text)
  get_filename_component(name ${f} NAME)
  string(FIND "${text}" ")QUIVER_EMBED\"" bad)
  if(NOT bad EQUAL -1)
    message(FATAL_ERROR "${f} contains the embedding delimiter")
  endif()
  string(APPEND body "  {\"${name}\", R\"QUIVER_EMBED(${text})QUIVER_EMBED\"},\n")
endforeach()
string(APPEND body "};\n}  // namespace\nstd::string_view embedded_file(std::string_view name) {\n  for (const File& f : kFiles) if (f.name == name) return f.text;\n  return {};\n}\n}  // namespace ${NAMESPACE}\n")
file(WRITE ${OUT} "${body}")

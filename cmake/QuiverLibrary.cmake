# quiver_add_library(<name> COMPONENT <component> SOURCES <src>...
#                    [PUBLIC <dep>...] [PRIVATE <dep>...] [BUILD_PRIVATE <dep>...])
#
# Compiles <src> once, as position-independent objects (<name>_objects), and makes two libraries
# of them: <name> (static; alias quiver::<short>, exported as quiver::<short>) and, when
# QUIVER_BUILD_SHARED is on, <name>_shared (exported as quiver::<short>_shared, output name
# lib<name>.so, so that `-l<name>` picks the shared one and `--static` the archive).
#
# PUBLIC and PRIVATE deps are linked to both; a dep named quiver_* is one of ours, and the shared
# library links the shared variant of it. BUILD_PRIVATE deps are used only to compile the objects
# (header-only libraries, generated sources): they never appear in the installed package.
# <short> is <name> without its "quiver_" prefix. The headers are <current dir>/include.
function(quiver_add_library name)
  cmake_parse_arguments(Q "" "COMPONENT" "SOURCES;PUBLIC;PRIVATE;BUILD_PRIVATE" ${ARGN})
  if(NOT Q_COMPONENT)
    message(FATAL_ERROR "quiver_add_library(${name}): COMPONENT is required")
  endif()
  string(REGEX REPLACE "^quiver_" "" short ${name})
  set(include_dir ${CMAKE_CURRENT_SOURCE_DIR}/include)

  add_library(${name}_objects OBJECT ${Q_SOURCES})
  set_target_properties(${name}_objects PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${name}_objects PUBLIC $<BUILD_INTERFACE:${include_dir}>)
  target_compile_features(${name}_objects PUBLIC cxx_std_20)
  target_link_libraries(${name}_objects PUBLIC ${Q_PUBLIC} PRIVATE ${Q_PRIVATE} ${Q_BUILD_PRIVATE})
  target_compile_options(${name}_objects PRIVATE ${QUIVER_WARNING_OPTIONS})

  set(variants ${name})
  add_library(${name} STATIC $<TARGET_OBJECTS:${name}_objects>)
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${short})
  target_link_libraries(${name} PUBLIC ${Q_PUBLIC} PRIVATE ${Q_PRIVATE})
  add_library(quiver::${short} ALIAS ${name})

  if(QUIVER_BUILD_SHARED)
    list(APPEND variants ${name}_shared)
    add_library(${name}_shared SHARED $<TARGET_OBJECTS:${name}_objects>)
    set_target_properties(${name}_shared PROPERTIES
      EXPORT_NAME ${short}_shared
      OUTPUT_NAME ${name}
      VERSION ${PROJECT_VERSION}
      SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
    foreach(kind PUBLIC PRIVATE)
      set(shared_deps)
      foreach(dep ${Q_${kind}})
        if(dep MATCHES "^quiver_" AND TARGET ${dep}_shared)
          list(APPEND shared_deps ${dep}_shared)
        else()
          list(APPEND shared_deps ${dep})
        endif()
      endforeach()
      target_link_libraries(${name}_shared ${kind} ${shared_deps})
    endforeach()
    add_library(quiver::${short}_shared ALIAS ${name}_shared)
  endif()

  foreach(t ${variants})
    target_include_directories(${t} PUBLIC
      $<BUILD_INTERFACE:${include_dir}>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_compile_features(${t} PUBLIC cxx_std_20)
  endforeach()

  if(QUIVER_INSTALL)
    install(TARGETS ${variants} EXPORT quiver-${Q_COMPONENT}-targets
      ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${Q_COMPONENT}
      LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${Q_COMPONENT}
      RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${Q_COMPONENT})
    install(DIRECTORY ${include_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
      COMPONENT ${Q_COMPONENT} FILES_MATCHING PATTERN "*.h")
  endif()
  set_property(GLOBAL APPEND PROPERTY QUIVER_COMPONENT_${Q_COMPONENT}_LIBS ${name})
endfunction()

# quiver_add_interface(<name> COMPONENT <component> LIBS <quiver_lib>...): an INTERFACE library
# bundling others (quiver::<short>, and quiver::<short>_shared bundling their shared variants).
function(quiver_add_interface name)
  cmake_parse_arguments(Q "" "COMPONENT" "LIBS" ${ARGN})
  string(REGEX REPLACE "^quiver_" "" short ${name})
  add_library(${name} INTERFACE)
  set_target_properties(${name} PROPERTIES EXPORT_NAME ${short})
  target_link_libraries(${name} INTERFACE ${Q_LIBS})
  add_library(quiver::${short} ALIAS ${name})
  set(variants ${name})
  if(QUIVER_BUILD_SHARED)
    list(TRANSFORM Q_LIBS APPEND _shared OUTPUT_VARIABLE shared_libs)
    add_library(${name}_shared INTERFACE)
    set_target_properties(${name}_shared PROPERTIES EXPORT_NAME ${short}_shared)
    target_link_libraries(${name}_shared INTERFACE ${shared_libs})
    add_library(quiver::${short}_shared ALIAS ${name}_shared)
    list(APPEND variants ${name}_shared)
  endif()
  if(QUIVER_INSTALL)
    install(TARGETS ${variants} EXPORT quiver-${Q_COMPONENT}-targets)
  endif()
endfunction()

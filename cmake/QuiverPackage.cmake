# The installed package: one CMake export set per component (quiver-<component>-targets.cmake,
# namespace quiver::), quiverConfig.cmake that re-finds only the dependencies of the components
# asked for, quiverConfigVersion.cmake, and one pkg-config file per component (quiver-<component>.pc).
include(CMakePackageConfigHelpers)
set(QUIVER_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/quiver)

foreach(component ${QUIVER_COMPONENTS})
  install(EXPORT quiver-${component}-targets
    NAMESPACE quiver::
    FILE quiver-${component}-targets.cmake
    DESTINATION ${QUIVER_CMAKE_DIR}
    COMPONENT ${component})
endforeach()

configure_package_config_file(cmake/quiverConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/quiverConfig.cmake
  INSTALL_DESTINATION ${QUIVER_CMAKE_DIR})
# 0.x: a minor release may change the API, so 0.2 accepts 0.2.* only.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/quiverConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
    ${CMAKE_CURRENT_BINARY_DIR}/quiverConfig.cmake
    ${CMAKE_CURRENT_BINARY_DIR}/quiverConfigVersion.cmake
  DESTINATION ${QUIVER_CMAKE_DIR}
  COMPONENT graph)

# pkg-config: -lquiver_x finds the shared library, `pkg-config --static` the archives.
set(QUIVER_PC_graph_REQUIRES "")
set(QUIVER_PC_graph_PRIVATE "")
set(QUIVER_PC_graph_LIBS "-lquiver_graph -lquiver_crdt -lquiver_base")
set(QUIVER_PC_interop_REQUIRES "quiver-graph = ${PROJECT_VERSION}")
set(QUIVER_PC_interop_PRIVATE "pugixml")
set(QUIVER_PC_interop_LIBS "-lquiver_interop")
set(QUIVER_PC_kinematics_REQUIRES "quiver-graph = ${PROJECT_VERSION}, eigen3, fcl")
set(QUIVER_PC_kinematics_PRIVATE "urdfdom")
set(QUIVER_PC_kinematics_LIBS "-lquiver_kinematics")
set(QUIVER_PC_agents_REQUIRES "quiver-graph = ${PROJECT_VERSION}, nlohmann_json")
set(QUIVER_PC_agents_PRIVATE "lmdb, pugixml")
set(QUIVER_PC_agents_LIBS "-lquiver_planning -lquiver_runtime -lquiver_agent_api -lquiver_planner -lquiver_mission -lquiver_symbolic -lquiver_store -lquiver_recording -lquiver_schema -lquiver_permissions -lquiver_locks -lquiver_grammar -lquiver_replication")
set(QUIVER_PC_dds_REQUIRES "quiver-agents = ${PROJECT_VERSION}, CycloneDDS, CLI11")
set(QUIVER_PC_dds_PRIVATE "spdlog, libcrypto")
set(QUIVER_PC_dds_LIBS "-lquiver_runtime_process -lquiver_agents_dds -lquiver_dds_transport -lquiver_wire -lquiver_security")
# cv::Mat is in quiver::images' API: opencv4 is a public requirement (its include path).
set(QUIVER_PC_sim_REQUIRES "quiver-agents = ${PROJECT_VERSION}, quiver-dds = ${PROJECT_VERSION}, opencv4")
set(QUIVER_PC_sim_PRIVATE "libgvc, libcgraph")
set(QUIVER_PC_sim_LIBS "-lquiver_barthel_process -lquiver_barthel_sim -lquiver_sim -lquiver_render -lquiver_render_rules -lquiver_barthel -lquiver_images -lquiver_devices")
set(QUIVER_PC_viewer_REQUIRES "quiver-sim = ${PROJECT_VERSION}, quiver-kinematics = ${PROJECT_VERSION}, nlohmann_json")
set(QUIVER_PC_viewer_PRIVATE "cpp-httplib")
set(QUIVER_PC_viewer_LIBS "-lquiver_viewer")
set(QUIVER_PC_agm_REQUIRES "quiver-sim = ${PROJECT_VERSION}, quiver-kinematics = ${PROJECT_VERSION}, nlohmann_json")
set(QUIVER_PC_agm_PRIVATE "")
set(QUIVER_PC_agm_LIBS "-lquiver_agm_sim -lquiver_agm")
if(TARGET quiver_agm_process)
  set(QUIVER_PC_agm_LIBS "-lquiver_agm_process ${QUIVER_PC_agm_LIBS}")
endif()
# Relocatable: the prefix is found from the .pc file's own place, so `cmake --install --prefix`
# anywhere gives working files.
file(RELATIVE_PATH QUIVER_PC_PREFIX_FROM_PCDIR
  /quiver-root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /quiver-root)
string(REGEX REPLACE "/$" "" QUIVER_PC_PREFIX_FROM_PCDIR "${QUIVER_PC_PREFIX_FROM_PCDIR}")
foreach(component ${QUIVER_COMPONENTS})
  set(QUIVER_PC_COMPONENT ${component})
  set(QUIVER_PC_REQUIRES "${QUIVER_PC_${component}_REQUIRES}")
  set(QUIVER_PC_PRIVATE "${QUIVER_PC_${component}_PRIVATE}")
  set(QUIVER_PC_LIBS "${QUIVER_PC_${component}_LIBS}")
  configure_file(cmake/quiver.pc.in ${CMAKE_CURRENT_BINARY_DIR}/quiver-${component}.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/quiver-${component}.pc
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
    COMPONENT ${component})
endforeach()

# The examples (programs, worlds, grammars, URDF, AGM files) with the package, so that the files
# the docs cite are on a machine that has only the package: PREFIX/share/quiver/examples.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/
  DESTINATION ${CMAKE_INSTALL_DATADIR}/quiver/examples
  COMPONENT graph)

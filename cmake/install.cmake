# `cmake --install build --prefix P`: headers, libraries, the qdmeta executable, the report
# tools, and the CMake package (find_package(qdmeta) with components rhex, mujoco and mpi).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(QDMETA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/qdmeta)
set(QDMETA_INSTALL_TOOLSDIR ${CMAKE_INSTALL_DATADIR}/qdmeta/tools)

# One export set per component: qdmetaConfig.cmake loads qdmetaRhexTargets.cmake and
# qdmetaMpiTargets.cmake (and searches for DART and MPI) only for a program that asks for them.
set(qdmeta_library_destinations ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS qdmeta qdmeta_command_line EXPORT qdmetaTargets ${qdmeta_library_destinations})
install(EXPORT qdmetaTargets NAMESPACE qdmeta:: DESTINATION ${QDMETA_INSTALL_CMAKEDIR})
# rhex_world.hpp is the rhex library's own (DART types): the installed RHex headers are DART-free.
set(qdmeta_header_excludes PATTERN rhex_world.hpp EXCLUDE)
if(QDMETA_WITH_RHEX)
  install(TARGETS qdmeta_rhex EXPORT qdmetaRhexTargets ${qdmeta_library_destinations})
  if(QDMETA_WITH_MUJOCO)
    install(TARGETS qdmeta_rhex_mujoco EXPORT qdmetaRhexTargets ${qdmeta_library_destinations})
    # The marker of component mujoco: the MuJoCo library the rhex targets link.
    file(WRITE ${PROJECT_BINARY_DIR}/qdmetaMujoco.cmake "set(_qdmeta_mujoco_library \"${QDMETA_MUJOCO_LIBRARY}\")\n")
    install(FILES ${PROJECT_BINARY_DIR}/qdmetaMujoco.cmake DESTINATION ${QDMETA_INSTALL_CMAKEDIR})
  endif()
  install(EXPORT qdmetaRhexTargets NAMESPACE qdmeta:: DESTINATION ${QDMETA_INSTALL_CMAKEDIR})
else()
  list(APPEND qdmeta_header_excludes PATTERN rhex EXCLUDE)
endif()
if(QDMETA_WITH_MPI)
  install(TARGETS qdmeta_mpi EXPORT qdmetaMpiTargets ${qdmeta_library_destinations})
  install(EXPORT qdmetaMpiTargets NAMESPACE qdmeta:: DESTINATION ${QDMETA_INSTALL_CMAKEDIR})
else()
  # eval/mpi/ and the command line's MPI Distribution (cli/mpi_distribution.hpp).
  list(APPEND qdmeta_header_excludes PATTERN mpi EXCLUDE PATTERN mpi_distribution.hpp EXCLUDE)
endif()

install(TARGETS qdmeta_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(QDMETA_WITH_RHEX)
  install(TARGETS qdmeta_rhex_gait RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/qdmeta DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp" ${qdmeta_header_excludes})
# report.py and run_summary.py import their modules from their own folder (claims, significance,
# the checked readers and writers of run files, the claim rules, the archive plots, runs and
# their summaries).
install(FILES ${PROJECT_SOURCE_DIR}/tools/report.py ${PROJECT_SOURCE_DIR}/tools/significance.py ${PROJECT_SOURCE_DIR}/tools/claims.py
              ${PROJECT_SOURCE_DIR}/tools/claim_rules.py ${PROJECT_SOURCE_DIR}/tools/experiment_files.py
              ${PROJECT_SOURCE_DIR}/tools/run_files.py ${PROJECT_SOURCE_DIR}/tools/output_files.py
              ${PROJECT_SOURCE_DIR}/tools/archive_plots.py ${PROJECT_SOURCE_DIR}/tools/runs.py
              ${PROJECT_SOURCE_DIR}/tools/run_summary.py ${PROJECT_SOURCE_DIR}/tools/script_exit.py
        DESTINATION ${QDMETA_INSTALL_TOOLSDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/qdmetaConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/qdmetaConfig.cmake
                              INSTALL_DESTINATION ${QDMETA_INSTALL_CMAKEDIR}
                              PATH_VARS QDMETA_INSTALL_TOOLSDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/qdmetaConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/qdmetaConfig.cmake ${PROJECT_BINARY_DIR}/qdmetaConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/qdmetaLinkCheck.cmake
        DESTINATION ${QDMETA_INSTALL_CMAKEDIR})

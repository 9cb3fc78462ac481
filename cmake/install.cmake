# `cmake --install build --prefix P`: headers, libraries, the qdmeta executable, the report
# tools, and the CMake package (find_package(qdmeta) with components rhex and mpi).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(QDMETA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/qdmeta)
set(QDMETA_INSTALL_TOOLSDIR ${CMAKE_INSTALL_DATADIR}/qdmeta/tools)

set(qdmeta_exported qdmeta qdmeta_command_line)
set(qdmeta_header_excludes)
if(QDMETA_WITH_RHEX)
  list(APPEND qdmeta_exported qdmeta_rhex)
else()
  list(APPEND qdmeta_header_excludes PATTERN rhex EXCLUDE)
endif()
if(QDMETA_WITH_MPI)
  list(APPEND qdmeta_exported qdmeta_mpi)
else()
  # eval/mpi/ and the command line's MPI Distribution (cli/mpi_distribution.hpp).
  list(APPEND qdmeta_header_excludes PATTERN mpi EXCLUDE PATTERN mpi_distribution.hpp EXCLUDE)
endif()

install(TARGETS ${qdmeta_exported} EXPORT qdmetaTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
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
              ${PROJECT_SOURCE_DIR}/tools/run_summary.py
        DESTINATION ${QDMETA_INSTALL_TOOLSDIR})

install(EXPORT qdmetaTargets NAMESPACE qdmeta:: DESTINATION ${QDMETA_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/qdmetaConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/qdmetaConfig.cmake
                              INSTALL_DESTINATION ${QDMETA_INSTALL_CMAKEDIR}
                              PATH_VARS QDMETA_INSTALL_TOOLSDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/qdmetaConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/qdmetaConfig.cmake ${PROJECT_BINARY_DIR}/qdmetaConfigVersion.cmake
        DESTINATION ${QDMETA_INSTALL_CMAKEDIR})

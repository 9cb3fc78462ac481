# qdmeta_test_programs: what `make test` builds, everything of the default build but bench/ and
# the test programs that only long tests run (QDMETA_LONG_TESTS_ONLY, tests/CMakeLists.txt):
# `make build`, `make bench` and CI's `make test-long` build those too. That is the libraries, the
# command line, the Python module and the test programs that `ctest -LE long` runs or the
# installed-package test installs. Collected from the folders' targets so that a new test program
# is never left out.
function(qdmeta_collect_built_targets folder out)
  get_property(targets DIRECTORY ${folder} PROPERTY BUILDSYSTEM_TARGETS)
  set(built "")
  foreach(target ${targets})
    get_target_property(type ${target} TYPE)
    get_target_property(excluded ${target} EXCLUDE_FROM_ALL)
    get_target_property(long_only ${target} QDMETA_LONG_TESTS_ONLY)
    if(type MATCHES "EXECUTABLE|LIBRARY" AND NOT type STREQUAL "INTERFACE_LIBRARY" AND NOT excluded AND NOT long_only)
      list(APPEND built ${target})
    endif()
  endforeach()
  get_property(subfolders DIRECTORY ${folder} PROPERTY SUBDIRECTORIES)
  foreach(subfolder ${subfolders})
    qdmeta_collect_built_targets(${subfolder} sub_built)
    list(APPEND built ${sub_built})
  endforeach()
  set(${out} ${built} PARENT_SCOPE)
endfunction()

add_custom_target(qdmeta_test_programs)
foreach(folder src apps python tests)
  if(EXISTS ${PROJECT_SOURCE_DIR}/${folder}/CMakeLists.txt AND (NOT folder STREQUAL "python" OR QDMETA_BUILD_PYTHON))
    qdmeta_collect_built_targets(${PROJECT_SOURCE_DIR}/${folder} folder_targets)
    if(folder_targets)
      add_dependencies(qdmeta_test_programs ${folder_targets})
    endif()
  endif()
endforeach()

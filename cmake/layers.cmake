# The layers of docs/architecture.md as build targets, so that a forbidden include fails the build.
#
# qdmeta_add_layers(SOURCES...) reads the ```layers block of docs/architecture.md (lowest layer
# first, one line per layer, as scripts/check-layers.py reads it) and makes, for each folder
# of src/qdmeta/ it names, the target qdmeta_layer_<folder>: an object library of that folder's
# SOURCES (an interface library where it has none). Its include path is a folder of the build
# tree holding only qdmeta/<folder> (a link to the sources), and it links the targets of the
# layer just below it, so that it sees its own headers and those of every lower layer and no
# other: an include of a higher layer or of another folder of its own layer is "No such file".
# tests/layers/ shows it. Sets qdmeta_layer_objects in the caller: the objects of every layer,
# which make the qdmeta library.
function(qdmeta_add_layers)
  file(READ ${PROJECT_SOURCE_DIR}/docs/architecture.md architecture)
  if(NOT architecture MATCHES "\n```layers\n([^`]*)```")
    message(FATAL_ERROR "docs/architecture.md has no ```layers block")
  endif()
  string(REPLACE "\n" ";" layers "${CMAKE_MATCH_1}")
  set(placed "")
  set(objects "")
  set(below "")
  foreach(layer IN LISTS layers)
    string(STRIP "${layer}" layer)
    if(layer STREQUAL "")
      continue()
    endif()
    string(REGEX REPLACE " +" ";" folders "${layer}")
    set(this_layer "")
    foreach(folder IN LISTS folders)
      if(NOT IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/qdmeta/${folder})
        continue()  # python/: the Python module's folder, outside src/qdmeta/
      endif()
      set(root ${CMAKE_CURRENT_BINARY_DIR}/layers/${folder})
      file(MAKE_DIRECTORY ${root}/qdmeta)
      file(REMOVE ${root}/qdmeta/${folder})
      file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR}/qdmeta/${folder} ${root}/qdmeta/${folder} SYMBOLIC)
      set(mine ${ARGN})
      list(FILTER mine INCLUDE REGEX "^qdmeta/${folder}/")
      list(APPEND placed ${mine})
      set(target qdmeta_layer_${folder})
      if(mine)
        add_library(${target} OBJECT ${mine})
        set(scope PUBLIC)
        list(APPEND objects $<TARGET_OBJECTS:${target}>)
        # The Python module (and a shared qdmeta) links these objects into a shared library.
        if(QDMETA_BUILD_PYTHON OR BUILD_SHARED_LIBS)
          set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
        endif()
      else()
        add_library(${target} INTERFACE)
        set(scope INTERFACE)
      endif()
      target_include_directories(${target} ${scope} ${root})
      target_link_libraries(${target} ${scope} qdmeta_layer_settings ${below})
      list(APPEND this_layer ${target})
    endforeach()
    set(below ${this_layer})
  endforeach()
  set(unplaced ${ARGN})
  list(REMOVE_ITEM unplaced ${placed})
  if(unplaced)
    message(FATAL_ERROR "sources in no folder of docs/architecture.md's ```layers block: ${unplaced}")
  endif()
  set(qdmeta_layer_objects ${objects} PARENT_SCOPE)
endfunction()

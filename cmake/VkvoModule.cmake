# vkvo_add_module(<name> DIR <dir> [DEPS <targets>...])
# One static library per layer, built from every .cpp under <dir> (globbed, so adding a file needs no CMake edit).
# Headers are included as "<layer>/<file>.hpp" relative to src/ (or "runtime/<file>.hpp").
# Designated initializers leave defaulted members out on purpose (C++20 idiom); GCC 12 warns about that even
# for members given as {}, so that one warning is off.
set(VKVO_WARNINGS -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
if(VKVO_WERROR)
  list(APPEND VKVO_WARNINGS -Werror)
endif()

function(vkvo_set_warnings target)
  target_compile_options(${target} PRIVATE ${VKVO_WARNINGS})
endfunction()

function(vkvo_add_module name)
  cmake_parse_arguments(ARG "" "DIR" "DEPS" ${ARGN})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${ARG_DIR}/*.cpp)
  if(NOT sources)
    message(FATAL_ERROR "vkvo_add_module(${name}): no .cpp under ${ARG_DIR}")
  endif()
  add_library(${name} STATIC ${sources})
  vkvo_set_warnings(${name})
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/vkvo>)
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  set_property(GLOBAL APPEND PROPERTY VKVO_MODULES ${name})
endfunction()

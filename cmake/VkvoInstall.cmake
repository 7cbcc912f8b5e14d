# Installs the libraries, headers and a CMake package so that another project can `find_package(vkvo)` and link
# `vkvo::vkvo`.
include(CMakePackageConfigHelpers)
get_property(modules GLOBAL PROPERTY VKVO_MODULES)

add_library(vkvo INTERFACE)
target_link_libraries(vkvo INTERFACE ${modules})
add_library(vkvo::vkvo ALIAS vkvo)

install(TARGETS vkvo ${modules} vkvo_shaders EXPORT vkvoTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS vkvo_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY runtime/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkvo/runtime FILES_MATCHING PATTERN "*.hpp")
install(DIRECTORY shaders/include/push DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkvo/shaders/include)  # push_constants.hpp
install(DIRECTORY src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkvo FILES_MATCHING PATTERN "*.hpp"
        PATTERN "app" EXCLUDE PATTERN "python" EXCLUDE)
install(DIRECTORY tools/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vkvo/tools FILES_MATCHING PATTERN "*.hpp")
install(EXPORT vkvoTargets NAMESPACE vkvo:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vkvo)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vkvoConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/vkvoConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vkvo)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/vkvoConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/vkvoConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/vkvoConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/vkvo)

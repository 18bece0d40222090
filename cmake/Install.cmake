# `cmake --install`: the library as a CMake package and the command-line program.
#
#   find_package(oitref CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE oitref::oit)   # scenes, methods, frames, image files
#
# oitref::core is formats, blending, depth and the pipeline (GLM and oneTBB only); oitref::scene
# loads scene files; oitref::oit adds the methods, the ground truths, image files and the one-call
# frame API (oitref/oit/frame.h); oitref::apps is the command line as a library (oitref/apps/cli.h: a
# program that registers its own methods and runs `oitref study` on them). The static libraries' own dependencies are found again by the
# package's config (Debian 12's packages, as for the build).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(_oitref_exported oitref_lib oitref_scene oitref_methods oitref_tools oitref_flags)
set_target_properties(oitref_lib PROPERTIES EXPORT_NAME core)
set_target_properties(oitref_scene PROPERTIES EXPORT_NAME scene)
set_target_properties(oitref_methods PROPERTIES EXPORT_NAME oit)
set_target_properties(oitref_tools PROPERTIES EXPORT_NAME apps)
set_target_properties(oitref_flags PROPERTIES EXPORT_NAME flags)
# The same names inside this build (for a project that adds oitref with add_subdirectory).
add_library(oitref::core ALIAS oitref_lib)
add_library(oitref::scene ALIAS oitref_scene)
add_library(oitref::oit ALIAS oitref_methods)
add_library(oitref::apps ALIAS oitref_tools)
foreach(_t IN LISTS _oitref_exported)
  target_include_directories(${_t} INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endforeach()

set(OITREF_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/oitref)
install(TARGETS ${_oitref_exported} EXPORT oitrefTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY include/oitref DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT oitrefTargets NAMESPACE oitref:: DESTINATION ${OITREF_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/oitrefConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/oitrefConfig.cmake
                              INSTALL_DESTINATION ${OITREF_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/oitrefConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/oitrefConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/oitrefConfigVersion.cmake
        DESTINATION ${OITREF_INSTALL_CMAKEDIR})
install(TARGETS oitref RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

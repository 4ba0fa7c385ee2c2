# `cmake --install build --prefix P`: headers under P/include/lieflow (included
# as <liegroup/so3.hpp>, <integrators/rkmk.hpp>, ... exactly as inside the
# tree), the libraries, the `lieflow` command, the built-in scenes, the plot
# scripts and the CMake package (lieflowConfig.cmake, version file, exported
# targets lieflow::liegroup, ::integrators, ::model, ::dynamics, ::simulation,
# ::joints (all three), ::calibration).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LIEFLOW_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/lieflow)
set(LIEFLOW_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/lieflow)

set(_lieflow_exported lieflow_liegroup lieflow_integrators lieflow_model lieflow_dynamics lieflow_simulation
    lieflow_joints)
set(_lieflow_header_dirs liegroup integrators model dynamics simulation)
if(LIEFLOW_HAVE_CERES)
  list(APPEND _lieflow_exported lieflow_calibration)
  list(APPEND _lieflow_header_dirs calibration)
endif()

foreach(_dir IN LISTS _lieflow_header_dirs)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${_dir}/ DESTINATION ${LIEFLOW_INSTALL_INCLUDEDIR}/${_dir}
          COMPONENT development FILES_MATCHING PATTERN "*.hpp")
endforeach()

install(TARGETS ${_lieflow_exported} EXPORT lieflowTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${LIEFLOW_INSTALL_INCLUDEDIR})
install(EXPORT lieflowTargets NAMESPACE lieflow:: DESTINATION ${LIEFLOW_INSTALL_CMAKEDIR}
        COMPONENT development)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/lieflowConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/lieflowConfig.cmake
                              INSTALL_DESTINATION ${LIEFLOW_INSTALL_CMAKEDIR})
# 0.x: a minor version may break the interface, so 0.1 accepts 0.1.* only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/lieflowConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/lieflowConfig.cmake ${PROJECT_BINARY_DIR}/lieflowConfigVersion.cmake
        DESTINATION ${LIEFLOW_INSTALL_CMAKEDIR} COMPONENT development)

install(TARGETS lieflow RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
file(GLOB _lieflow_scene_files ${PROJECT_SOURCE_DIR}/scenes/*.json)
install(FILES ${_lieflow_scene_files} DESTINATION ${CMAKE_INSTALL_DATADIR}/lieflow/scenes COMPONENT runtime)
# The study and stability plots (app/plotting.cpp finds them next to bin/).
install(FILES ${PROJECT_SOURCE_DIR}/scripts/plot_study.py ${PROJECT_SOURCE_DIR}/scripts/plot_stability.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/lieflow/scripts COMPONENT runtime)

# `cmake --install BUILD [--prefix DIR]`: the library, its headers, the `vascsim` command, the Python module,
# the bundled scenes, data and scripts, and the CMake package vascsim::vascsim (docs/api.md, "Install layout").
# Two components: runtime (what `vascsim` and `import vascsim` need) and dev (headers, CMake package, the
# linker's libvascsim.so), the two .deb packages of `make package` (cmake/VascsimPackage.cmake).
include(CMakePackageConfigHelpers)

set(VASCSIM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/vascsim)

# Installed programs and the Python module find libvascsim relative to themselves ($ORIGIN), so a prefix can
# be moved as a whole; nothing when the library goes to a folder the loader searches anyway (/usr/lib/...).
list(FIND CMAKE_PLATFORM_IMPLICIT_LINK_DIRECTORIES "${CMAKE_INSTALL_FULL_LIBDIR}" VASCSIM_LIBDIR_IS_SYSTEM)
function(vascsim_set_install_rpath target installed_in)
  if(VASCSIM_SHARED AND VASCSIM_LIBDIR_IS_SYSTEM EQUAL -1)
    file(RELATIVE_PATH rel /prefix/${installed_in} /prefix/${CMAKE_INSTALL_LIBDIR})
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/${rel}")
  endif()
endfunction()

install(TARGETS vascsim EXPORT vascsimTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
vascsim_set_install_rpath(vascsim_app ${CMAKE_INSTALL_BINDIR})
install(TARGETS vascsim_app RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)

# The Python package (python/CMakeLists.txt chose VASCSIM_PYTHON_DIR): the module beside __init__.py.
if(VASCSIM_BUILD_PYTHON)
  vascsim_set_install_rpath(vascsim_python ${VASCSIM_PYTHON_DIR}/vascsim)
  install(TARGETS vascsim_python LIBRARY DESTINATION ${VASCSIM_PYTHON_DIR}/vascsim COMPONENT runtime)
  file(GLOB VASCSIM_PYTHON_PACKAGE_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/python/vascsim/*.py)
  install(FILES ${VASCSIM_PYTHON_PACKAGE_FILES} DESTINATION ${VASCSIM_PYTHON_DIR}/vascsim COMPONENT runtime)
endif()

# The library's headers, as vascsim/<layer>/<file>.hpp (the renderer and the viewer are not a public API).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/vascsim DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev
  FILES_MATCHING PATTERN "*.hpp" PATTERN "render" EXCLUDE PATTERN "viewer" EXCLUDE)

# The bundled files (core/bundled_files.hpp): scenes/ and data/ keep their relative links (scenes/aorta-vmtk.json
# reads ../data/vessels/...); scripts/ holds the plot scripts the experiments run and the other plotting tools.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes ${PROJECT_SOURCE_DIR}/data DESTINATION ${VASCSIM_INSTALL_DATADIR}
  COMPONENT runtime)
file(GLOB VASCSIM_SCRIPTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/scripts/*.py)
install(PROGRAMS ${VASCSIM_SCRIPTS} DESTINATION ${VASCSIM_INSTALL_DATADIR}/scripts COMPONENT runtime)

# The CMake package: find_package(vascsim) gives vascsim::vascsim with its dependencies found again.
install(EXPORT vascsimTargets NAMESPACE vascsim:: DESTINATION ${VASCSIM_INSTALL_CMAKEDIR} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vascsimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/vascsimConfig.cmake INSTALL_DESTINATION ${VASCSIM_INSTALL_CMAKEDIR})
# Before 1.0 every minor version may change the API (docs/api.md, "What is stable").
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vascsimConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vascsimConfig.cmake ${PROJECT_BINARY_DIR}/vascsimConfigVersion.cmake
  DESTINATION ${VASCSIM_INSTALL_CMAKEDIR} COMPONENT dev)

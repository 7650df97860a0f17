# `make package` (cpack -G DEB): two Debian packages from the install components (cmake/VascsimInstall.cmake),
# for an install prefix of /usr (the Makefile configures the package build with -DCMAKE_INSTALL_PREFIX=/usr):
#   vascsim      the library, the `vascsim` command, the Python module, the bundled scenes, data and scripts;
#                Depends from dpkg-shlibdeps (the Debian packages of the shared libraries it links) plus Python
#   vascsim-dev  the headers, libvascsim.so and the CMake package; Depends on the -dev packages of the headers
# scripts/check-deb-in-chroot.sh installs them on a fresh Debian 12 (docs/api.md, "Debian package").
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME vascsim)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "point-primitive vascular tissue simulation (Zhang et al. 2021)")
set(CPACK_PACKAGE_CONTACT "vascsim developers")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME vascsim)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# A shlibs file for libvascsim.so.0.1: a package linking it depends on exactly this version (the ABI is not
# stable before 1.0).
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY "=")
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "point-primitive vascular tissue simulation: library, command line, Python module
 vascsim simulates blood-vessel tissue for interventional-surgery training (the point-primitive method of
 Zhang et al. 2021): the vascsim command runs scenes, experiments and the viewer; import vascsim drives it
 from Debian's python3. Bundled scenes, data and plot scripts are in /usr/share/vascsim.")
# Beyond the linked libraries (dpkg-shlibdeps): the Python module is built for this python3 and uses NumPy;
# the plot scripts the experiments run need matplotlib; headless pictures (vascsim view --screenshot) need Mesa.
set(VASCSIM_DEB_DEPENDS "")
if(VASCSIM_BUILD_PYTHON)
  math(EXPR VASCSIM_PYTHON_NEXT_MINOR "${Python_VERSION_MINOR} + 1")
  set(VASCSIM_DEB_DEPENDS "python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), python3 (<< ${Python_VERSION_MAJOR}.${VASCSIM_PYTHON_NEXT_MINOR}), python3-numpy")
endif()
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "${VASCSIM_DEB_DEPENDS}")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "python3-matplotlib, python3-numpy, libegl1, libgl1-mesa-dri, libegl-mesa0")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME vascsim-dev)
set(CPACK_COMPONENT_DEV_DESCRIPTION "point-primitive vascular tissue simulation: headers and CMake package
 C++ headers of libvascsim and its CMake package: find_package(vascsim) and link vascsim::vascsim.")
set(VASCSIM_DEB_DEV_DEPENDS "vascsim (= ${PROJECT_VERSION}), libeigen3-dev (>= 3.4), nlohmann-json3-dev (>= 3.10), libfmt-dev, libspdlog-dev")
if(NOT VASCSIM_SHARED)
  string(APPEND VASCSIM_DEB_DEV_DEPENDS ", libassimp-dev, libcli11-dev, libsuitesparse-dev, libblas-dev")
endif()
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "${VASCSIM_DEB_DEV_DEPENDS}")
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)

include(CPack)

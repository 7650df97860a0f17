# Decides VASCSIM_BUILD_PYTHON, the Python module (python/): on by default when Debian's pybind11-dev and
# python3-dev are there for VASCSIM_PYTHON_EXECUTABLE (not whatever python3 comes first on PATH), off by
# default in a sanitizer or fuzzing build (a Python process would have to preload the sanitizer runtime).
if(NOT DEFINED VASCSIM_BUILD_PYTHON OR VASCSIM_BUILD_PYTHON)
  set(Python_EXECUTABLE ${VASCSIM_PYTHON_EXECUTABLE})
  find_package(Python 3 COMPONENTS Interpreter Development.Module QUIET)
  if(Python_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
  endif()
endif()
if(Python_FOUND AND pybind11_FOUND AND NOT VASCSIM_SANITIZE AND NOT VASCSIM_FUZZ)
  set(VASCSIM_PYTHON_DEFAULT ON)
else()
  set(VASCSIM_PYTHON_DEFAULT OFF)
endif()
option(VASCSIM_BUILD_PYTHON "Build the Python module (pybind11)" ${VASCSIM_PYTHON_DEFAULT})
if(VASCSIM_BUILD_PYTHON AND NOT (Python_FOUND AND pybind11_FOUND))
  message(FATAL_ERROR "VASCSIM_BUILD_PYTHON is ON but pybind11 or the Python headers for "
    "${VASCSIM_PYTHON_EXECUTABLE} were not found: install pybind11-dev and python3-dev "
    "(scripts/install-deps.sh), or configure with -DVASCSIM_BUILD_PYTHON=OFF.")
endif()
if(VASCSIM_BUILD_PYTHON)
  message(STATUS "Python module: for ${Python_EXECUTABLE} (${Python_VERSION}), pybind11 ${pybind11_VERSION}")
endif()

# `import oitref`: the Python module (src/apps/python/module.cpp), built into build/python and
# installed by `cmake --install` into the prefix's Python site-packages. Needs Debian's
# pybind11-dev, python3-dev and python3-numpy (scripts/setup.sh installs them); without them
# nothing else changes.
option(OITREF_PYTHON "Build the Python module when pybind11 is found" ON)
set(OITREF_HAVE_PYTHON OFF)
if(OITREF_PYTHON AND NOT OITREF_FUZZ AND NOT OITREF_SANITIZE)
  # Debian's interpreter, whose numpy and pytest come from the same packages (a python3 earlier
  # in PATH, e.g. pyenv's, has neither); -DPython3_EXECUTABLE=... chooses another.
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 COMPONENTS Interpreter Development.Module QUIET)
  find_package(pybind11 CONFIG QUIET)
  if(Python3_FOUND AND pybind11_FOUND)
    set(OITREF_HAVE_PYTHON ON)
  else()
    message(STATUS "oitref Python module not built: needs pybind11-dev and python3-dev")
  endif()
endif()
if(OITREF_HAVE_PYTHON)
  pybind11_add_module(oitref_python MODULE NO_EXTRAS src/apps/python/module.cpp)  # no LTO: build time
  set_target_properties(oitref_python PROPERTIES OUTPUT_NAME oitref LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/python)
  target_link_libraries(oitref_python PRIVATE oitref_methods)
  # A shared module links the static libraries, so they are position-independent; without
  # semantic interposition GCC still inlines and calls their functions directly, as in the program.
  foreach(_t oitref_lib oitref_scene oitref_methods)
    set_target_properties(${_t} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(${_t} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
  endforeach()
  # Relative to the install prefix: lib/python3.X/dist-packages on Debian (its sysconfig puts a
  # "local/" before it, which a prefix of /usr/local already is), site-packages elsewhere.
  execute_process(COMMAND ${Python3_EXECUTABLE} -c
    "import sysconfig; p = sysconfig.get_path('platlib', vars={'platbase': '', 'base': ''}).lstrip('/'); print(p[6:] if p.startswith('local/') else p)"
    OUTPUT_VARIABLE _oitref_site OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(OITREF_PYTHON_INSTALL_DIR ${_oitref_site} CACHE STRING "Where `cmake --install` puts the Python module, under the prefix")
  install(TARGETS oitref_python LIBRARY DESTINATION ${OITREF_PYTHON_INSTALL_DIR})
  # Installed, it finds the image module (liboitref_imageio.so) through its run path.
  file(RELATIVE_PATH _oitref_to_module /prefix/${OITREF_PYTHON_INSTALL_DIR} /prefix/${CMAKE_INSTALL_LIBDIR}/oitref)
  set_target_properties(oitref_python PROPERTIES INSTALL_RPATH "$ORIGIN/${_oitref_to_module}")
  message(STATUS "oitref: Python module (import oitref from ${CMAKE_BINARY_DIR}/python)")
endif()

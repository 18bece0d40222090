# Dependencies, all from Debian 12 packages. A missing one stops configuration with the name of
# the package that provides it (scripts/setup.sh installs them all).

macro(oitref_require pkg debian)
  find_package(${pkg} ${ARGN} QUIET)
  if(NOT ${pkg}_FOUND)
    message(FATAL_ERROR "oitref needs ${pkg}: install the Debian package '${debian}' "
                        "(apt-get install ${debian}, or run scripts/setup.sh)")
  endif()
endmacro()

oitref_require(glm libglm-dev)
oitref_require(TBB libtbb-dev)

# The core layer's only dependencies; each higher layer finds its own in its CMakeLists.txt
# (GLOBAL: the targets that link a layer's libraries from elsewhere, the tests and the installed
# package's checks, see its dependencies too).

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
oitref_require(CLI11 libcli11-dev)
oitref_require(embree libembree-dev 3)
oitref_require(assimp libassimp-dev)
oitref_require(nlohmann_json nlohmann-json3-dev)

# OpenImageIO. Debian 12's OpenImageIOTargets.cmake lists /usr/include/opencv4 among the
# interface include directories although libopenimageio-dev does not depend on OpenCV; CMake
# refuses imported targets with non-existent include paths at generation time. We keep the real
# target and wrap it in oitref_oiio, copying only the include directories that exist.
# Its config also names the openimageio-tools binaries (iconvert, ...), so both packages are needed.
oitref_require(OpenImageIO "libopenimageio-dev openimageio-tools")
include(OpenImageIOFix)
add_library(oitref_oiio INTERFACE)
target_link_libraries(oitref_oiio INTERFACE OpenImageIO::OpenImageIO)

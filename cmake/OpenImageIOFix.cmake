# Debian 12's OpenImageIO::OpenImageIO lists include directories that do not exist
# (/usr/include/opencv4), which CMake refuses at generation time: keep only those that exist.
# Used by this build (src/oit/CMakeLists.txt) and by the installed package's config.
get_target_property(_oiio_incs OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
set(_oiio_existing "")
foreach(_dir IN LISTS _oiio_incs)
  if(EXISTS "${_dir}")
    list(APPEND _oiio_existing "${_dir}")
  endif()
endforeach()
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${_oiio_existing}"
  INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "")

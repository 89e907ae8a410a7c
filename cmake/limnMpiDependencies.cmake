# SPDX-License-Identifier: MIT
# The MPI layer's libraries besides MPI itself, found the same way when limn
# is built (CMakeLists.txt) and when an installed limn is used
# (limnConfig.cmake, COMPONENTS mpi): each becomes an IMPORTED target that
# limn_mpi links. A new dependency of the MPI layer is one line at the end:
#   _limn_mpi_library(TARGET HEADER LIBRARY_NAME [HEADER_SUBDIRECTORY...])
# Missing ones are listed in LIMN_MPI_MISSING (their names, for the message).
macro(_limn_mpi_library target header name)
  if(NOT TARGET ${target})
    string(MAKE_C_IDENTIFIER "${target}" _limn_dep)
    find_path(LIMN_${_limn_dep}_INCLUDE_DIR ${header} PATH_SUFFIXES ${ARGN})
    find_library(LIMN_${_limn_dep}_LIBRARY ${name})
    if(LIMN_${_limn_dep}_INCLUDE_DIR AND LIMN_${_limn_dep}_LIBRARY)
      add_library(${target} UNKNOWN IMPORTED GLOBAL)
      set_target_properties(${target} PROPERTIES
        IMPORTED_LOCATION "${LIMN_${_limn_dep}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${LIMN_${_limn_dep}_INCLUDE_DIR}")
    else()
      list(APPEND LIMN_MPI_MISSING ${name})
    endif()
  endif()
  list(APPEND LIMN_MPI_DEPENDENCIES ${target})
endmacro()

set(LIMN_MPI_MISSING)
set(LIMN_MPI_DEPENDENCIES)
_limn_mpi_library(limn::metis metis.h metis)
# PT-Scotch (libptscotch-dev: headers in include/scotch, no pkg-config file);
# Debian's libptscotch holds the sequential Scotch routines too
_limn_mpi_library(limn::ptscotch ptscotch.h ptscotch scotch)
_limn_mpi_library(limn::ptscotcherr ptscotch.h ptscotcherr scotch)

# SPDX-License-Identifier: MIT
# The installable limn: liblimn.so (only the LIMN_API functions exported)
# and liblimn.a (internal symbols made local, so that they cannot clash with
# an application's), both from limn_objects; limn.h; the limn CLI; a CMake
# package (find_package(limn): limn::limn, limn::limn_static) and pkg-config
# files (limn.pc; limn-static.pc for the archive). README "Embedding limn".
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LIMN_DIST_DIR ${CMAKE_BINARY_DIR}/lib)
# 0.x: every minor version may change the ABI
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(LIMN_SOVERSION 0.${PROJECT_VERSION_MINOR})
else()
  set(LIMN_SOVERSION ${PROJECT_VERSION_MAJOR})
endif()
set(LIMN_PUBLIC_INCLUDE $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                        $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)

add_library(limn_shared SHARED $<TARGET_OBJECTS:limn_objects>)
set_target_properties(limn_shared PROPERTIES OUTPUT_NAME limn EXPORT_NAME limn
                      VERSION ${PROJECT_VERSION} SOVERSION ${LIMN_SOVERSION}
                      LIBRARY_OUTPUT_DIRECTORY ${LIMN_DIST_DIR})
target_include_directories(limn_shared INTERFACE ${LIMN_PUBLIC_INCLUDE})
target_link_libraries(limn_shared PRIVATE OpenCL::OpenCL PkgConfig::HWLOC Threads::Threads m)
if(NOT LIMN_SANITIZE AND NOT LIMN_FUZZ)
  # the .so names everything it needs (sanitizer runtimes come from the program)
  target_link_options(limn_shared PRIVATE LINKER:--no-undefined)
endif()

# One relocatable object with every hidden symbol made local, archived.
if(NOT CMAKE_OBJCOPY)
  message(FATAL_ERROR "objcopy (binutils) is needed to build liblimn.a")
endif()
set(LIMN_STATIC_OBJECT ${CMAKE_CURRENT_BINARY_DIR}/limn_static.o)
add_custom_command(
  OUTPUT ${LIMN_STATIC_OBJECT}
  COMMAND ${CMAKE_LINKER} -r -o ${LIMN_STATIC_OBJECT} $<TARGET_OBJECTS:limn_objects>
  COMMAND ${CMAKE_OBJCOPY} --localize-hidden ${LIMN_STATIC_OBJECT}
  DEPENDS limn_objects $<TARGET_OBJECTS:limn_objects>
  COMMAND_EXPAND_LISTS
  COMMENT "Linking liblimn.a's object, internal symbols made local")
set_source_files_properties(${LIMN_STATIC_OBJECT} PROPERTIES EXTERNAL_OBJECT TRUE GENERATED TRUE)
add_library(limn_static STATIC ${LIMN_STATIC_OBJECT})
set_target_properties(limn_static PROPERTIES OUTPUT_NAME limn EXPORT_NAME limn_static
                      LINKER_LANGUAGE C ARCHIVE_OUTPUT_DIRECTORY ${LIMN_DIST_DIR})
target_include_directories(limn_static INTERFACE ${LIMN_PUBLIC_INCLUDE})
target_link_libraries(limn_static INTERFACE OpenCL::OpenCL PkgConfig::HWLOC Threads::Threads m)

set(LIMN_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/limn)
install(TARGETS limn_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS limn_shared EXPORT limnTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS limn_static EXPORT limnStaticTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/limn.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# two export sets: limn::limn must not need OpenCL's or hwloc's development files
install(EXPORT limnTargets NAMESPACE limn:: DESTINATION ${LIMN_CMAKE_DIR})
install(EXPORT limnStaticTargets NAMESPACE limn:: DESTINATION ${LIMN_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/limnConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/limnConfig.cmake
                              INSTALL_DESTINATION ${LIMN_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/limnConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/limnConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/limnConfigVersion.cmake
        DESTINATION ${LIMN_CMAKE_DIR})

# pkg-config: paths relative to the .pc file, so that `cmake --install
# --prefix P` (or moving the tree) keeps them right
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(LIMN_PC_PREFIX ${CMAKE_INSTALL_PREFIX})
  set(LIMN_PC_LIBDIR ${CMAKE_INSTALL_FULL_LIBDIR})
  set(LIMN_PC_INCLUDEDIR ${CMAKE_INSTALL_FULL_INCLUDEDIR})
else()
  file(RELATIVE_PATH up /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
  set(LIMN_PC_PREFIX "\${pcfiledir}/${up}")
  set(LIMN_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(LIMN_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
foreach(pc limn limn-static)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${pc}.pc.in ${CMAKE_CURRENT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/${pc}.pc
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()

# The MPI layer, installable (include/limn_mpi.h): liblimn_mpi.so and
# liblimn_mpi.a carry the layer and their own copy of limn's internals and
# export only limn_mpi.h's functions (a version script; objcopy for the
# archive), so they sit beside liblimn.so / liblimn.a, which the program links
# for limn.h's functions (limn_context_create, limn_mesh_read, ...): one
# version of limn for both. find_package(limn COMPONENTS mpi): limn::mpi
# (and limn::mpi_static); pkg-config: limn-mpi.pc.
if(LIMN_MPI_ENABLED)
  set(LIMN_MPI_EXPORTS ${CMAKE_CURRENT_BINARY_DIR}/limn_mpi.map)
  file(WRITE ${LIMN_MPI_EXPORTS} "{ global: limn_mpi_*; limn_*_mpi; local: *; };\n")
  add_library(limn_mpi_shared SHARED $<TARGET_OBJECTS:limn_mpi_objects>
              $<TARGET_OBJECTS:limn_objects>)
  set_target_properties(limn_mpi_shared PROPERTIES OUTPUT_NAME limn_mpi EXPORT_NAME mpi
                        VERSION ${PROJECT_VERSION} SOVERSION ${LIMN_SOVERSION}
                        LIBRARY_OUTPUT_DIRECTORY ${LIMN_DIST_DIR} LINK_DEPENDS ${LIMN_MPI_EXPORTS})
  target_include_directories(limn_mpi_shared INTERFACE ${LIMN_PUBLIC_INCLUDE})
  target_link_options(limn_mpi_shared PRIVATE LINKER:--version-script=${LIMN_MPI_EXPORTS})
  if(NOT LIMN_SANITIZE AND NOT LIMN_FUZZ)
    target_link_options(limn_mpi_shared PRIVATE LINKER:--no-undefined)
  endif()
  target_link_libraries(limn_mpi_shared PUBLIC MPI::MPI_C INTERFACE limn_shared
                        PRIVATE ${LIMN_MPI_DEPENDENCIES} OpenCL::OpenCL PkgConfig::HWLOC
                                Threads::Threads m)

  set(LIMN_MPI_STATIC_OBJECT ${CMAKE_CURRENT_BINARY_DIR}/limn_mpi_static.o)
  add_custom_command(
    OUTPUT ${LIMN_MPI_STATIC_OBJECT}
    COMMAND ${CMAKE_LINKER} -r -o ${LIMN_MPI_STATIC_OBJECT} $<TARGET_OBJECTS:limn_mpi_objects>
            $<TARGET_OBJECTS:limn_objects>
    COMMAND ${CMAKE_OBJCOPY} --localize-hidden -w --keep-global-symbol=limn_mpi_*
            --keep-global-symbol=limn_*_mpi ${LIMN_MPI_STATIC_OBJECT}
    DEPENDS limn_mpi_objects limn_objects $<TARGET_OBJECTS:limn_mpi_objects>
            $<TARGET_OBJECTS:limn_objects>
    COMMAND_EXPAND_LISTS
    COMMENT "Linking liblimn_mpi.a's object, all but limn_mpi.h's symbols made local")
  set_source_files_properties(${LIMN_MPI_STATIC_OBJECT} PROPERTIES EXTERNAL_OBJECT TRUE
                              GENERATED TRUE)
  add_library(limn_mpi_static STATIC ${LIMN_MPI_STATIC_OBJECT})
  set_target_properties(limn_mpi_static PROPERTIES OUTPUT_NAME limn_mpi EXPORT_NAME mpi_static
                        LINKER_LANGUAGE C ARCHIVE_OUTPUT_DIRECTORY ${LIMN_DIST_DIR})
  target_include_directories(limn_mpi_static INTERFACE ${LIMN_PUBLIC_INCLUDE})
  target_link_libraries(limn_mpi_static INTERFACE limn_static MPI::MPI_C
                        ${LIMN_MPI_DEPENDENCIES})

  install(TARGETS limn_mpi_shared EXPORT limnMpiTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(TARGETS limn_mpi_static EXPORT limnMpiStaticTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(FILES ${PROJECT_SOURCE_DIR}/include/limn_mpi.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT limnMpiTargets NAMESPACE limn:: DESTINATION ${LIMN_CMAKE_DIR})
  install(EXPORT limnMpiStaticTargets NAMESPACE limn:: DESTINATION ${LIMN_CMAKE_DIR})
  install(FILES ${CMAKE_CURRENT_LIST_DIR}/limnMpiDependencies.cmake DESTINATION ${LIMN_CMAKE_DIR})

  # limn-mpi.pc: MPI's own compile and link flags, as CMake found them
  set(LIMN_PC_MPI_CFLAGS ${MPI_C_COMPILE_OPTIONS})
  foreach(d ${MPI_C_COMPILE_DEFINITIONS})
    list(APPEND LIMN_PC_MPI_CFLAGS -D${d})
  endforeach()
  foreach(d ${MPI_C_INCLUDE_DIRS})
    list(APPEND LIMN_PC_MPI_CFLAGS -I${d})
  endforeach()
  set(LIMN_PC_MPI_LIBS ${MPI_C_LINK_FLAGS} ${MPI_C_LIBRARIES})
  list(JOIN LIMN_PC_MPI_CFLAGS " " LIMN_PC_MPI_CFLAGS)
  list(JOIN LIMN_PC_MPI_LIBS " " LIMN_PC_MPI_LIBS)
  configure_file(${CMAKE_CURRENT_LIST_DIR}/limn-mpi.pc.in ${CMAKE_CURRENT_BINARY_DIR}/limn-mpi.pc
                 @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/limn-mpi.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()

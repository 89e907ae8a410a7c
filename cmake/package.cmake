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

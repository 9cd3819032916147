# Install rules and the CMake package (CC_INSTALL): headers under include/crowdcloth, the
# libraries, and lib/cmake/crowdcloth with crowdcloth::crowdcloth and crowdcloth::import.
include(CMakePackageConfigHelpers)

set(cc_install_targets crowdcloth)
get_target_property(cc_install_headers crowdcloth CC_PUBLIC_HEADERS)
if(CC_BUILD_IMPORT)
    list(APPEND cc_install_targets cc_import)
    get_target_property(cc_import_headers cc_import CC_PUBLIC_HEADERS)
    list(APPEND cc_install_headers ${cc_import_headers})
endif()
if(NOT BUILD_SHARED_LIBS)
    # A static archive does not contain the archives it links: the internal ones are installed
    # beside it and exported as link-only dependencies (their headers are not installed).
    get_property(cc_internal GLOBAL PROPERTY CC_INTERNAL_LIBRARIES)
    list(APPEND cc_install_targets ${cc_internal})
endif()

install(TARGETS ${cc_install_targets} EXPORT crowdclothTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${cc_install_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/crowdcloth)

# The package's config needs the link dependencies of a static build only.
if(BUILD_SHARED_LIBS)
    set(CC_PACKAGE_SHARED ON)
else()
    set(CC_PACKAGE_SHARED OFF)
endif()
set(cc_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/crowdcloth)
install(EXPORT crowdclothTargets NAMESPACE crowdcloth:: DESTINATION ${cc_package_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/crowdclothConfig.cmake.in
    ${PROJECT_BINARY_DIR}/crowdclothConfig.cmake INSTALL_DESTINATION ${cc_package_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/crowdclothConfigVersion.cmake
    COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/crowdclothConfig.cmake
              ${PROJECT_BINARY_DIR}/crowdclothConfigVersion.cmake
        DESTINATION ${cc_package_dir})

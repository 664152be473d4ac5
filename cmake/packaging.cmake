# Installing and packaging: `cmake --install build [--prefix P]` puts bin/rayfarm, the man page
# rayfarm(1) made from the same text as --help (cmake/make_man.cmake), and the docs under the
# prefix; `cd build && cpack -G DEB` makes rayfarm_VERSION_ARCH.deb whose dependencies are the
# Debian runtime packages of the libraries it links (dpkg-shlibdeps, from dpkg-dev) and
# openmpi-bin for mpirun. Included at the end of farm/CMakeLists.txt.
include(GNUInstallDirs)

set(RAYFARM_MAN ${CMAKE_BINARY_DIR}/man/rayfarm.1)
add_custom_command(OUTPUT ${RAYFARM_MAN}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/man
  COMMAND ${CMAKE_COMMAND} -DRAYFARM=$<TARGET_FILE:rayfarm> -DVERSION=${PROJECT_VERSION} -DOUT=${RAYFARM_MAN}
          -DVIEW=$<BOOL:${Qt6Widgets_FOUND}>
          -P ${PROJECT_SOURCE_DIR}/cmake/make_man.cmake
  DEPENDS rayfarm ${PROJECT_SOURCE_DIR}/cmake/make_man.cmake
  COMMENT "rayfarm.1 from rayfarm --help")
add_custom_target(rayfarm_man ALL DEPENDS ${RAYFARM_MAN})

install(TARGETS rayfarm RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${RAYFARM_MAN} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/docs/cli.md ${PROJECT_SOURCE_DIR}/docs/farm.md ${PROJECT_SOURCE_DIR}/docs/pictures.md
              ${PROJECT_SOURCE_DIR}/docs/architecture.md ${PROJECT_SOURCE_DIR}/docs/building.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(CPACK_PACKAGE_NAME rayfarm)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "ray tracer and MPI render farm: glTF models and scene files to turntable films")
set(CPACK_PACKAGE_CONTACT "rayfarm maintainers <rayfarm@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # rayfarm_0.1_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Not libraries it links, so dpkg-shlibdeps cannot see them: the launcher a farm runs it under,
# and libavfilter, which a GIF's writer opens (dlopen) when it needs it.
string(REGEX MATCH "^[0-9]+" RAYFARM_AVFILTER_MAJOR "${AVFILTER_VERSION}")
set(CPACK_DEBIAN_PACKAGE_DEPENDS "openmpi-bin, libavfilter${RAYFARM_AVFILTER_MAJOR}")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "assimp-testmodels")
include(CPack)

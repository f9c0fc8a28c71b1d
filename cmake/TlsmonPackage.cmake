# The Debian package of a release (README, "Installing a release package"):
# `cpack -G DEB` in the build folder (deploy/build-package.sh) packs what `install` puts
# under /usr — tlsmon and tlsmon-analysis, the dashboard's files — and, from deploy/ and
# etc/, the systemd unit, the default configuration (a conffile, paths in /var/lib/tlsmon),
# the documentation, and the maintainer scripts of deploy/debian/ (a `tlsmon` system user,
# its state folders, the unit enabled). Depends are computed by dpkg-shlibdeps.
include(GNUInstallDirs)
set(_pkg ${PROJECT_BINARY_DIR}/package)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${PROJECT_SOURCE_DIR}/etc/tlsmon.toml ${PROJECT_SOURCE_DIR}/deploy/tlsmon.service)

# The shipped configuration with the installed state folder (as deploy/install.sh writes it).
file(READ ${PROJECT_SOURCE_DIR}/etc/tlsmon.toml _toml)
foreach(_f ingest archive quarantine tlsmon.sqlite)
  string(REPLACE "\"../var/${_f}\"" "\"/var/lib/tlsmon/${_f}\"" _toml "${_toml}")
endforeach()
file(WRITE ${_pkg}/tlsmon.toml "${_toml}")
# The unit with the package's paths.
file(READ ${PROJECT_SOURCE_DIR}/deploy/tlsmon.service _unit)
string(REPLACE "/usr/local/" "/usr/" _unit "${_unit}")
string(REPLACE "(installed by deploy/install.sh)" "(installed by the tlsmon package)" _unit "${_unit}")
file(WRITE ${_pkg}/tlsmon.service "${_unit}")
# Maintainer scripts with the permissions dpkg requires, whatever the checkout's umask.
file(COPY ${PROJECT_SOURCE_DIR}/deploy/debian/postinst ${PROJECT_SOURCE_DIR}/deploy/debian/prerm
          ${PROJECT_SOURCE_DIR}/deploy/debian/postrm DESTINATION ${_pkg}
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ
                      WORLD_EXECUTE)
file(COPY ${PROJECT_SOURCE_DIR}/deploy/debian/conffiles DESTINATION ${_pkg}
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ WORLD_READ)

install(FILES ${_pkg}/tlsmon.toml DESTINATION /etc/tlsmon)
install(FILES ${_pkg}/tlsmon.service DESTINATION /lib/systemd/system)
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        FILES_MATCHING PATTERN "*.md" PATTERN "*.yaml" PATTERN "*.png" PATTERN "*.svg")
install(FILES deploy/debian/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The Debian changelog, compressed as policy wants it (gzip -9n: no name, no time stamp).
add_custom_command(
  OUTPUT ${_pkg}/changelog.Debian.gz
  COMMAND gzip -9nc ${PROJECT_SOURCE_DIR}/deploy/debian/changelog > ${_pkg}/changelog.Debian.gz
  DEPENDS ${PROJECT_SOURCE_DIR}/deploy/debian/changelog)
add_custom_target(tlsmon_changelog ALL DEPENDS ${_pkg}/changelog.Debian.gz)
install(FILES ${_pkg}/changelog.Debian.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})

# Manual pages, made from the programs' own --help and --version by help2man (installed by
# deploy/install-deps.sh --tests, which the package is built with); tlsmon-analysis, which
# `tlsmon` calls with the same arguments, points to tlsmon's page.
find_program(HELP2MAN help2man)
if(HELP2MAN)
  add_custom_command(
    OUTPUT ${_pkg}/tlsmon.1.gz ${_pkg}/tlsmon-analysis.1.gz
    COMMAND ${HELP2MAN} --no-info --section 1 --version-string ${PROJECT_VERSION}
            --name "unattended deformation monitoring with a terrestrial laser scanner"
            --output ${_pkg}/tlsmon.1 $<TARGET_FILE:tlsmon>
    COMMAND gzip -9nf ${_pkg}/tlsmon.1
    COMMAND ${CMAKE_COMMAND} -E echo ".so man1/tlsmon.1" > ${_pkg}/tlsmon-analysis.1
    COMMAND gzip -9nf ${_pkg}/tlsmon-analysis.1
    DEPENDS tlsmon tlsmon-analysis)
  add_custom_target(tlsmon_man ALL DEPENDS ${_pkg}/tlsmon.1.gz)
  install(FILES ${_pkg}/tlsmon.1.gz ${_pkg}/tlsmon-analysis.1.gz
          DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME tlsmon)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGE_CONTACT "tlsmon developers <tlsmon@example.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "deformation monitoring with a terrestrial laser scanner")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "unattended deformation monitoring with a terrestrial laser scanner\n tlsmon watches a structure (a bridge pier, a dam) through a laser scanner that\n stays on site: every scan is recorded as an epoch, registered on targets or\n stable areas, compared with the reference epoch (M3C2, keypoints, patches),\n stored as per-zone time series, and raises ISA-18.2 alarms over Modbus TCP,\n a web dashboard and notifications.")
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    "${_pkg}/postinst;${_pkg}/prerm;${_pkg}/postrm;${_pkg}/conffiles")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)

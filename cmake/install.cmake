# `cmake --install` and the Debian package (CPack). Standard prefixes
# (GNUInstallDirs): the binary in bin/, man pages written from the CLI's own
# help in share/man/man1/ (gzipped), bash and zsh completion, the example missions in
# share/strata/missions/, the phase library in share/strata/library/ (where
# an installed strata looks for `import NAME;` and `:- use_phase(NAME).`:
# src/coral/loader.h, library_dirs()), the docs, LICENSE and NOTICE in
# share/doc/strata/ with the Debian copyright file and changelog.
include(GNUInstallDirs)

# The man pages and completion scripts: written by the built strata after
# each link (src/cli/CMakeLists.txt), into:
set(STRATA_GEN_DIR ${PROJECT_BINARY_DIR}/generated)

install(TARGETS strata strata-pnml RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The studio's HTTP server, loaded by strata from BINDIR/../LIBDIR/strata/modules
# (src/studio/http_module.h). Two folders below LIBDIR, not one: CPack
# (CPackDeb.cmake) has the package run ldconfig on install and removal for
# any shared object one folder below /usr/lib, which ld.so does not search
# for a private module (lintian: maintscript-calls-ldconfig).
install(TARGETS strata_studio_http LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/strata/modules)
# The precompiled PROLOG driver, loaded by strata from BINDIR/../LIBDIR/strata
# (src/strategic/prolog_driver_precompiled.h); built with strata_strategic.
install(FILES ${STRATA_PRECOMPILED_DRIVER} DESTINATION ${CMAKE_INSTALL_LIBDIR}/strata)
# Gzipped by the build (cmake/gzip_man_pages.cmake); man reads them so.
install(DIRECTORY ${STRATA_GEN_DIR}/man/ DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 FILES_MATCHING PATTERN "*.1.gz")
install(FILES ${STRATA_GEN_DIR}/completion/strata.bash
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/bash-completion/completions RENAME strata)
install(FILES ${STRATA_GEN_DIR}/completion/_strata DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/zsh/vendor-completions)
install(FILES ${STRATA_GEN_DIR}/completion/strata-pnml.bash
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/bash-completion/completions RENAME strata-pnml)
install(FILES ${STRATA_GEN_DIR}/completion/_strata-pnml
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/zsh/vendor-completions)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/missions/ DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/strata/missions
        PATTERN "*.layout.json" EXCLUDE PATTERN "runs" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/library/ DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/strata/library
        FILES_MATCHING PATTERN "*.coral" PATTERN "*.pl")
install(FILES ${PROJECT_SOURCE_DIR}/config/phoenix.toml ${PROJECT_SOURCE_DIR}/config/primitives.toml
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/strata/config)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/NOTICE
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
# What Debian asks of every package (Policy 12.5 and 12.7): the copyright
# file, machine-readable (DEP-5), and the changelog, gzipped with -9n (no
# name or time stamp: the same bytes at each build). Strata is its own
# upstream, a native package: changelog.gz, not changelog.Debian.gz.
install(FILES ${PROJECT_SOURCE_DIR}/cmake/debian/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
find_program(STRATA_GZIP gzip REQUIRED)
file(MAKE_DIRECTORY ${STRATA_GEN_DIR}/debian)
execute_process(COMMAND ${STRATA_GZIP} -9nc INPUT_FILE ${PROJECT_SOURCE_DIR}/cmake/debian/changelog
                OUTPUT_FILE ${STRATA_GEN_DIR}/debian/changelog.gz COMMAND_ERROR_IS_FATAL ANY)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/cmake/debian/changelog)
install(FILES ${STRATA_GEN_DIR}/debian/changelog.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The Debian package: `cpack -G DEB` in a build folder (docs/install.md).
set(CPACK_PACKAGE_NAME strata)
set(CPACK_PACKAGE_VENDOR "The Strata authors")
# No address is published for Strata yet: .example is reserved (RFC 2606),
# never delivered. The same contact heads cmake/debian/changelog's entry and
# cmake/debian/copyright; whoever publishes the package puts theirs in all three.
set(CPACK_PACKAGE_CONTACT "The Strata authors <maintainers@strata.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Strategic-level mission control for AUVs (CORAL Petri nets and PROLOG rules)")
# Lines of at most 80 characters (Debian Policy 3.4.1); CPack keeps them.
string(JOIN "\n" CPACK_PACKAGE_DESCRIPTION
  "Strata runs AUV missions written as CORAL Petri nets or PROLOG rules"
  "against a simulated NPS Phoenix, a real vehicle speaking its protocol or"
  "an IMC vehicle (LSTS DUNE). It verifies CORAL missions before they run,"
  "with the shortest counterexample for each problem, and shows missions live"
  "in its studio, a graphical editor in the browser. Campaigns run a mission"
  "over many scenarios, on this machine or on Slurm; a run's log is plotted"
  "with gnuplot."
  ""
  "The package holds the strata program, the studio's HTTP module, man pages,"
  "bash and zsh completion, the example missions and the phase library.")
# Native: Strata is packaged by its own authors; the changelog is
# cmake/debian/changelog, whose first entry must be this version.
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)          # library packages from the binary (dpkg-shlibdeps)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "gnuplot-nox, chromium")
set(CPACK_GENERATOR DEB)
include(CPack)

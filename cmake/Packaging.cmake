# The Debian package: `make package` (or `cpack -G DEB` in the build tree)
# writes cubecal_<version>_<arch>.deb with everything `cmake --install` puts
# under /usr: the cubecal command and its man pages, the static libraries,
# the headers and the CMake package (find_package(cubecal)), the Python
# module (import cubecal), README.md and the copyright file. ctest checks it
# (test package_deb, label package: tests/package_check.sh).
#
# Included last by CMakeLists.txt; the fuzz configuration installs nothing and
# packages nothing, the Python-only one (the wheel's) packages nothing.
if(CUBECAL_FUZZ OR CUBECAL_PYTHON_ONLY)
  return()
endif()

# ---------------------------------------------------------------------------
# Man pages, generated from --help by help2man: cubecal(1) for the program and
# its subcommands, one page per subcommand (cubecal-analyze(1) ...), gzipped.
set(CUBECAL_MAN_DIR "${PROJECT_BINARY_DIR}/man")
find_program(CUBECAL_HELP2MAN help2man)
find_program(CUBECAL_GZIP gzip)
if(CUBECAL_BUILD_CLI AND (NOT CUBECAL_HELP2MAN OR NOT CUBECAL_GZIP))
  message(WARNING "help2man or gzip not found: the package has no man pages (scripts/install-deps.sh installs both)")
elseif(CUBECAL_BUILD_CLI)
  # Subcommand (words of the command line) and the NAME line of its page.
  set(_cubecal_man_pages
    "dev|Allan-family deviations with Stable32-compatible confidence intervals"
    "analyze|static characterization: noise terms, sensor models, drift, covariance, temperature"
    "simulate|simulate sensor records from presets or from an analyze result"
    "calibrate|calibration from lab logs"
    "calibrate rate-table|gyro scale factors, misalignment and bias from rate-table plateaus"
    "calibrate mag|magnetometer hard- and soft-iron calibration"
    "calibrate temperature|polynomial bias(T) per channel"
    "calibrate multiposition|accelerometer and gyroscope calibration from static poses"
    "turnon|turn-on bias over power-cycled runs"
    "compare|Allan curves of several runs side by side"
    "davar|dynamic Allan deviation: OADEV over a sliding window, a tau x time matrix per channel"
    "psd|power spectral density (Welch), its power-law fit and the noise terms it stands for"
    "model|composite noise model (white, quantization, random walk, drift, Gauss-Markov) fitted by GMWM"
    "plan|how long to record: the record length each noise term needs for a target precision"
    "report|HTML report of an analyze result"
    "demo|the 72 h static experiment of the CubeSat sensor study, simulated and analyzed")

  set(_see_also "")
  foreach(_entry IN LISTS _cubecal_man_pages)
    string(REGEX REPLACE "\\|.*" "" _words "${_entry}")
    string(REPLACE " " "-" _page "cubecal-${_words}")
    list(APPEND _see_also "${_page}")
  endforeach()
  list(JOIN _see_also " (1),\n.BR " _see_also)
  # (file(CONFIGURE) rewrites a file only when its text changes: the pages are
  # not generated anew on every configuration.)
  file(CONFIGURE OUTPUT "${CUBECAL_MAN_DIR}/see-also-cubecal.h2m"
    CONTENT "[SEE ALSO]\n.BR ${_see_also} (1)\n\nThe README.md in /usr/share/doc/cubecal.\n")
  file(CONFIGURE OUTPUT "${CUBECAL_MAN_DIR}/see-also-subcommand.h2m"
    CONTENT "[SEE ALSO]\n.BR cubecal (1)\n")

  # help2man runs `cubecal WORDS --help`; the version comes from the project.
  function(cubecal_man_page page words name include)
    if(words STREQUAL "")
      set(_help "--help")
    else()
      set(_help "${words} --help")
    endif()
    add_custom_command(
      OUTPUT "${CUBECAL_MAN_DIR}/${page}.1.gz"
      COMMAND "${CUBECAL_HELP2MAN}" --no-info "--name=${name}" "--help-option=${_help}"
              "--version-string=${page} ${PROJECT_VERSION}" "--include=${include}"
              "--output=${CUBECAL_MAN_DIR}/${page}.1" "$<TARGET_FILE:cubecal>"
      COMMAND "${CUBECAL_GZIP}" -9 -n -f "${CUBECAL_MAN_DIR}/${page}.1"
      DEPENDS cubecal "${include}"
      COMMENT "Generating man page ${page}(1)"
      VERBATIM)
  endfunction()

  set(CUBECAL_MAN_PAGES "${CUBECAL_MAN_DIR}/cubecal.1.gz")
  cubecal_man_page(cubecal "" "Allan variance, noise models and calibration of inertial sensors and clocks"
    "${CUBECAL_MAN_DIR}/see-also-cubecal.h2m")
  foreach(_entry IN LISTS _cubecal_man_pages)
    string(REPLACE "|" ";" _entry "${_entry}")
    list(GET _entry 0 _words)
    list(GET _entry 1 _name)
    string(REPLACE " " "-" _page "cubecal-${_words}")
    cubecal_man_page("${_page}" "${_words}" "${_name}" "${CUBECAL_MAN_DIR}/see-also-subcommand.h2m")
    list(APPEND CUBECAL_MAN_PAGES "${CUBECAL_MAN_DIR}/${_page}.1.gz")
  endforeach()
  add_custom_target(cubecal_man ALL DEPENDS ${CUBECAL_MAN_PAGES})
  install(FILES ${CUBECAL_MAN_PAGES} DESTINATION "${CMAKE_INSTALL_MANDIR}/man1")
endif()

# ---------------------------------------------------------------------------
# /usr/share/doc/cubecal: README.md and the copyright file.
file(CONFIGURE OUTPUT "${PROJECT_BINARY_DIR}/packaging/copyright" CONTENT
"Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/
Upstream-Name: cubecal
Upstream-Contact: cubecal developers

Files: *
Copyright: cubecal developers
License: not-stated
 The cubecal sources do not state a licence.
")
install(FILES "${PROJECT_SOURCE_DIR}/README.md" "${PROJECT_BINARY_DIR}/packaging/copyright"
  DESTINATION "${CMAKE_INSTALL_DOCDIR}")

# ---------------------------------------------------------------------------
# CPack: one .deb with every install component.
set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "cubecal")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_VENDOR "cubecal developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Allan variance, noise and calibration of gyroscopes, magnetometers, clocks")
set(CPACK_PACKAGE_DESCRIPTION
"cubecal characterizes, models, simulates and calibrates the attitude sensors
of small satellites (MEMS gyroscopes, magnetometers, accelerometers) and the
clocks of time-and-frequency labs: Allan-family deviations (adev, oadev, mdev,
tdev, hdev, ohdev, totdev) with Stable32-compatible confidence intervals,
IEEE 952 noise terms and sensor noise models, bias drift, covariance and
temperature coefficients, sensor simulation, and rate-table, magnetometer,
temperature and multi-position calibrations.

This package holds the cubecal command-line tool with its man pages, the C++
library (static libraries, headers and the CMake package for
find_package(cubecal)) and the Python module (import cubecal).")
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)
set(CPACK_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
  OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "cubecal developers")
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
set(CPACK_DEBIAN_COMPRESSION_TYPE "xz")
# The shared libraries of the binary and of the Python extension (libc6,
# libstdc++6, libgomp1, libfmt, libhdf5 ...), computed by dpkg-shlibdeps.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The Python module: the interpreter its extension was built for (the
# extension is tied to that minor version) and NumPy.
set(_cubecal_depends "")
if(CUBECAL_BUILD_PYTHON)
  if(CUBECAL_PYTHON_INSTALL_DIR MATCHES "python([0-9]+)\\.([0-9]+)")
    math(EXPR _next_minor "${CMAKE_MATCH_2} + 1")
    list(APPEND _cubecal_depends
      "python3 (>= ${CMAKE_MATCH_1}.${CMAKE_MATCH_2}~)" "python3 (<< ${CMAKE_MATCH_1}.${_next_minor})")
  else()
    list(APPEND _cubecal_depends "python3")
  endif()
  list(APPEND _cubecal_depends "python3-numpy")
endif()
list(JOIN _cubecal_depends ", " CPACK_DEBIAN_PACKAGE_DEPENDS)
# gnuplot draws the plots of the reports (--report).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "gnuplot-nox")
# The Python package's byte code, as Debian's Python packages do it:
# compiled after installation (py3compile, python3-minimal) and removed
# before removal (py3clean), so that `apt remove` leaves no __pycache__.
if(CUBECAL_BUILD_PYTHON)
  set(_scripts "${PROJECT_BINARY_DIR}/deb-scripts")
  file(WRITE "${_scripts}/postinst" "#!/bin/sh\nset -e\nif [ \"$1\" = configure ] && command -v py3compile >/dev/null 2>&1; then\n  py3compile -p cubecal\nfi\n")
  file(WRITE "${_scripts}/prerm" "#!/bin/sh\nset -e\nif command -v py3clean >/dev/null 2>&1; then\n  py3clean -p cubecal\nfi\n")
  file(CHMOD "${_scripts}/postinst" "${_scripts}/prerm" PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
  set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA "${_scripts}/postinst;${_scripts}/prerm")
endif()

include(CPack)

# ---------------------------------------------------------------------------
# ctest -R package_deb (or -L package): builds the .deb in a scratch
# directory, checks its fields and contents, runs the extracted binary and
# imports the extracted Python module; a configuration without the command or
# the module makes a package the test would refuse, and does not register it.
if(CUBECAL_BUILD_TESTS AND CUBECAL_BUILD_CLI AND CUBECAL_BUILD_PYTHON)
  add_test(NAME package_deb
    COMMAND bash "${PROJECT_SOURCE_DIR}/tests/package_check.sh" "${PROJECT_BINARY_DIR}" "${PROJECT_VERSION}")
  set_tests_properties(package_deb PROPERTIES LABELS package TIMEOUT 600)
elseif(CUBECAL_BUILD_TESTS)
  message(STATUS "cubecal: test package_deb needs CUBECAL_BUILD_CLI and CUBECAL_BUILD_PYTHON: not registered")
endif()

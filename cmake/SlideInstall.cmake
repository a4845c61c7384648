# `cmake --install BUILD --prefix PREFIX`: what a user needs to run the pipeline on a
# case of their own with only PREFIX/bin on PATH (docs/install.md):
#   bin/                       the programs and slide-new-case
#   share/slide/cases/         the Make pipeline (pipeline.mk, paths.mk, out.mk), the
#                              template case, and installed.mk naming the installed
#                              programs and tools (written at install time, so that
#                              --prefix given to `cmake --install` is the one it names)
#   share/slide/tools/         the pipeline's Python and shell tools, the slide Python
#                              module (PYTHONPATH=PREFIX/share/slide/tools) and its example
#   share/doc/slide/           the documentation, in the source tree's layout (links work)
#   lib/cmake/slide/           a CMake package: find_package(slide) gives the programs as
#                              imported targets slide::fem-solve, ... and the pipeline's
#                              and tools' folders (slide_PIPELINE_MK, slide_TOOLS_DIR)
include(CMakePackageConfigHelpers)

set(slide_programs fem-solve fem2mpm mpm-solve slide-metrics slide-element opensees2fem
                   mpm2cbgeo)
install(TARGETS ${slide_programs} EXPORT slideTargets RUNTIME DESTINATION bin)
install(PROGRAMS tools/slide-new-case DESTINATION bin)

install(FILES cases/pipeline.mk cases/paths.mk cases/out.mk DESTINATION share/slide/cases)
install(DIRECTORY cases/template DESTINATION share/slide/cases PATTERN out EXCLUDE)
install(CODE [[
  set(slide_share "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/share/slide")
  file(WRITE "${slide_share}/cases/installed.mk"
"# Written by cmake --install: the installed programs and tools (paths.mk reads it).
SLIDE_INSTALLED_BIN := ${CMAKE_INSTALL_PREFIX}/bin
SLIDE_INSTALLED_SHARE := ${CMAKE_INSTALL_PREFIX}/share/slide
")
  message(STATUS "Installing: ${slide_share}/cases/installed.mk")
]])

file(GLOB slide_tool_scripts CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tools/*.py)
install(PROGRAMS ${slide_tool_scripts} tools/clean-outputs.sh DESTINATION share/slide/tools)
install(DIRECTORY tools/slide tools/examples DESTINATION share/slide/tools
        PATTERN __pycache__ EXCLUDE)

install(FILES README.md LICENSE CITATION.cff CHANGELOG.md DESTINATION share/doc/slide)
install(DIRECTORY docs cases common fem mpm transfer tools DESTINATION share/doc/slide
        FILES_MATCHING PATTERN "*.md" PATTERN "*.png"
        PATTERN out EXCLUDE PATTERN build EXCLUDE)

install(EXPORT slideTargets NAMESPACE slide:: DESTINATION lib/cmake/slide)
set(SLIDE_SHARE_DIR share/slide)  # relative: the package finds it from where it lies
configure_package_config_file(cmake/slideConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/slideConfig.cmake
                              INSTALL_DESTINATION lib/cmake/slide PATH_VARS SLIDE_SHARE_DIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/slideConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/slideConfig.cmake
              ${PROJECT_BINARY_DIR}/slideConfigVersion.cmake
        DESTINATION lib/cmake/slide)

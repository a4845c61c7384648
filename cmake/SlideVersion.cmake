# The commit a build was configured from, for `--version`, the checkpoints' `producer`
# attribute and the reports: `git describe --always --dirty` of the source tree, or
# "unknown" outside a Git checkout (a source archive). CMake configures again whenever
# HEAD moves (a commit, a checkout), so a new commit shows without a manual reconfigure;
# edits made after the last configure are not seen until the next commit.
set(SLIDE_COMMIT "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} rev-parse --absolute-git-dir
                  OUTPUT_VARIABLE slide_git_dir OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                  RESULT_VARIABLE slide_git_status)
  if(slide_git_status EQUAL 0 AND EXISTS ${slide_git_dir}/HEAD)
    execute_process(COMMAND ${GIT_EXECUTABLE} -C ${PROJECT_SOURCE_DIR} describe --always --dirty
                            --abbrev=12
                    OUTPUT_VARIABLE slide_describe OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                    RESULT_VARIABLE slide_git_status)
    if(slide_git_status EQUAL 0 AND slide_describe)
      set(SLIDE_COMMIT ${slide_describe})
    endif()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${slide_git_dir}/HEAD)
    if(EXISTS ${slide_git_dir}/logs/HEAD)  # the reflog: written by every commit and checkout
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${slide_git_dir}/logs/HEAD)
    endif()
  endif()
endif()
message(STATUS "slide ${PROJECT_VERSION}, commit ${SLIDE_COMMIT}")

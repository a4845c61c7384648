# SLIDE_FUZZ=ON: every target of the project compiled for libFuzzer (tests/fuzz/): coverage
# instrumentation, AddressSanitizer and UndefinedBehaviorSanitizer (an undefined
# behaviour stops the run, as a crash does), frame pointers and debug information for
# symbolised stacks. The drivers themselves add -fsanitize=fuzzer at link time
# (tests/fuzz/CMakeLists.txt). Debian 12: apt-get install clang-16 libclang-rt-16-dev
# libomp-16-dev llvm-16 (tools/fuzz.sh does it; clang 14 cannot compile the project).
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "SLIDE_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++-16 -DCMAKE_C_COMPILER=clang-16), "
                      "not ${CMAKE_CXX_COMPILER_ID}")
endif()
add_compile_options(
  -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
  -fno-omit-frame-pointer -g)
add_link_options(-fsanitize=address,undefined)

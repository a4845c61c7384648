# SLIDE_SANITIZE=ON builds every target (libraries, programs, tests, benchmarks) with
# AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer. Any undefined
# behaviour stops the program (-fno-sanitize-recover), like a memory error does, so a
# report can never scroll past in a test that otherwise passes. Frame pointers keep the
# reports' stacks whole. Use it through the `sanitize` preset (CMakePresets.json) or
# tools/sanitize.sh, which also set the run-time options (ASAN_OPTIONS, UBSAN_OPTIONS).
if(SLIDE_SANITIZE)
  set(slide_sanitizer_flags
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_compile_options(${slide_sanitizer_flags})
  add_link_options(${slide_sanitizer_flags})
  message(STATUS "slide: sanitizers on (${slide_sanitizer_flags})")
endif()

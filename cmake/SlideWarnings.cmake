# Warnings are errors in our own code. Third-party headers come in as SYSTEM
# includes (imported targets), so their warnings do not stop the build.
add_library(slide_warnings INTERFACE)
target_compile_options(slide_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Wunused -Woverloaded-virtual -Wconversion -Wno-sign-conversion
  -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough
  -Werror
  # GCC 12 reports a false "may be used uninitialized" inside its own AVX-512
  # intrinsics whenever Eigen's vectorised products are inlined with -march=native
  # (GCC bug 105593, fixed in GCC 13).
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-maybe-uninitialized>)

add_library(slide_optimisation INTERFACE)
# A square root is one instruction instead of a test and a library call kept for errno,
# which nothing here reads (results are the same: √ of a negative is NaN either way).
target_compile_options(slide_optimisation INTERFACE -fno-math-errno)
if(SLIDE_NATIVE)
  target_compile_options(slide_optimisation INTERFACE $<$<CONFIG:Release,RelWithDebInfo>:-march=native>)
endif()

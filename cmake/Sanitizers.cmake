# Instrumented builds (docs/robustness.md), set up before any target so that every library, the command line
# and the tests are compiled the same way:
#   TETHER_SANITIZE  AddressSanitizer + UndefinedBehaviorSanitizer
#   TETHER_FUZZ      the same sanitizers plus libFuzzer's coverage instrumentation, and the targets in fuzz/
#                    (clang only)
# scripts/dev sanitize and scripts/dev fuzz share one clang build with both (build-asan/).
# Any undefined behaviour is fatal (-fno-sanitize-recover), so a report fails the test or the fuzzing run.
option(TETHER_SANITIZE "Build with -fsanitize=address,undefined" OFF)
option(TETHER_FUZZ "Build the libFuzzer targets in fuzz/ (clang only; implies the sanitizers)" OFF)

set(TETHER_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
if(TETHER_SANITIZE OR TETHER_FUZZ)
  add_compile_options(${TETHER_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
  # Eigen 3.4 stops trusting malloc's 16-byte alignment under __SANITIZE_ADDRESS__ and then over-allocates and
  # offsets its buffers; Debian's libceres was built without ASan and frees Eigen buffers the plain way. Where the
  # two meet (Ceres' Covariance runs Eigen templates instantiated by both; a consumer of the library frees a
  # Scene's vectors) ASan reports "attempting free on address which was not malloc()-ed". Keep the uninstrumented
  # choice everywhere: glibc's and ASan's malloc both return 16-byte aligned blocks on x86_64, and Eigen asserts
  # that alignment in Debug builds.
  add_compile_definitions(EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()
if(TETHER_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TETHER_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # coverage feedback for everything; only the fuzz targets link libFuzzer's main
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

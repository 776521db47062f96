# Warnings for our own targets only: link strata_warnings PRIVATE.
# STRATA_WERROR (on in the presets CI builds) makes each of them an error,
# so that the tree stays at zero warnings.
option(STRATA_WERROR "Treat compiler warnings in Strata's own code as errors" OFF)
add_library(strata_warnings INTERFACE)
target_compile_options(strata_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual -Wimplicit-fallthrough
  $<$<BOOL:${STRATA_WERROR}>:-Werror>
  # GCC 12 reports -Wmaybe-uninitialized inside libstdc++'s std::regex and
  # std::function when ASan's or TSan's instrumentation is inlined at -O1 (a
  # known false positive of GCC's, in code that is not ours); the debug and
  # release builds keep the warning.
  $<$<OR:$<BOOL:${STRATA_SANITIZE}>,$<BOOL:${STRATA_SANITIZE_THREAD}>>:-Wno-maybe-uninitialized>
  # GCC before 13 reports -Wrestrict on std::string's operator+ when it is
  # inlined at -O2 (GCC bug 105329: memcpy "accessing 9223372036854775810 or
  # more bytes"), 12 times in the release build; later GCCs do not.
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>)

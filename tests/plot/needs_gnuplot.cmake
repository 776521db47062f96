# strata_plot_needs_gnuplot(): in a plot test's script, ends the script
# (a macro's return() leaves its caller) with "skipped: ..." when gnuplot
# is not on PATH; ctest counts that as a skip (SKIP_REGULAR_EXPRESSION).
macro(strata_plot_needs_gnuplot)
  find_program(GNUPLOT gnuplot)
  if(NOT GNUPLOT)
    message("skipped: gnuplot is not on PATH (Debian: apt-get install gnuplot-nox)")
    return()
  endif()
endmacro()

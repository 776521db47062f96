#include "cli/exit_codes.h"

#include <string_view>

namespace strata::cli {

const char* exit_code_help() {
  return "Exit codes: 0 ok (a run: the mission completed), 1 the mission did not complete (aborted, failed,\n"
         "halted, a limit reached), 64 usage, 65 invalid mission, 69 unavailable (gnuplot missing; strata sonar:\n"
         "the vehicle unreachable or gone; campaign --submit: sbatch missing or failing), 70 internal error,\n"
         "74 I/O error (a file or the vehicle cannot be reached), 128+N ended by signal N (129 SIGHUP,\n"
         "130 SIGINT, 143 SIGTERM; a run surfaces first).\n"
         "Every command takes -q/--quiet (results and errors only) and -v/--verbose (more detail);\n"
         "`strata COMMAND --help` lists its options and its own exit codes.";
}

const char* exit_codes_of(std::string_view command) {
  if (command == "dump") {
    return "Exit 0 when the mission compiled and was printed; 64 usage (an unknown --net: the nets are listed);\n"
           "65 when the mission does not compile; 74 when a file cannot be read.";
  }
  if (command == "run") {
    return "Exit 0 when the mission completed; 1 when it did not (aborted, failed, halted, a limit reached;\n"
           "the vehicle is surfaced first); 64 usage; 65 invalid mission, data, scenario or --answers file, or\n"
           "a run that left its --answers script (surfaced first); 70 internal error;\n"
           "74 a file or the vehicle cannot be reached; 128+N ended by signal N (129 SIGHUP, 130 SIGINT,\n"
           "143 SIGTERM), the vehicle surfaced first.";
  }
  if (command == "compare") {
    return "Exit 0 when the two traces are identical; 1 when they differ; 64 usage; 65 invalid mission or\n"
           "scenario; 70 internal error; 74 a file cannot be read.";
  }
  if (command == "export") {
    return "Exit 0 when written; 64 usage (PROLOG rules, an unknown --net); 65 when the mission does not\n"
           "compile; 74 when a file cannot be read or written.";
  }
  if (command == "vehicle") {
    return "Exit 0 after Ctrl-C or SIGTERM; 64 usage (a bad --listen, --port or --imc-id, an option --imc\n"
           "does not take); 65 invalid parameters or scenario;\n"
           "74 when it cannot listen or read a file.";
  }
  if (command == "primitives") {
    return "Exit 0 when printed; 64 usage; 65 an invalid catalogue; 74 when the catalogue cannot be read.";
  }
  if (command == "library") {
    return "Exit 0 when printed; 64 usage; 65 when a CORAL module of the library does not compile or\n"
           "declares no phase net of its name (each problem printed).";
  }
  if (command == "campaign") {
    return "Exit 0 when every case met its expectations (--compare: no verdict or outcome changed); 1 when\n"
           "some did not (--compare: one changed); 64 usage; 65 an invalid spec; 69 --submit: sbatch missing or\n"
           "failing (the scripts are written); 74 a file cannot be read or\n"
           "the results folder written; 128+N ended by signal N (130 SIGINT, 143 SIGTERM): the finished cases\n"
           "are kept.";
  }
  if (command == "completion") return "Exit 0 when printed; 64 for a shell other than bash or zsh.";
  return nullptr;
}

}  // namespace strata::cli

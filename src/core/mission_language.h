#pragma once
// Which language a mission file is written in: CORAL (a .coral file) or
// PROLOG (a .pl file). Decided here alone, by the file's extension, for
// every command, the studio, runs and campaigns.
#include <string_view>

namespace strata::core {

enum class MissionLanguage { None, Coral, Prolog };

// The language of the mission file at path, by the extension of its name
// (as std::filesystem::path::extension() gives it: ".pl" alone is a name
// without one). None for any other file: a scenario, a log, a folder.
MissionLanguage mission_language(std::string_view path);

// "coral" or "prolog", as JSON outputs and the studio spell a mission's
// language; "" for None.
std::string_view language_key(MissionLanguage language);

// "CORAL" or "PROLOG", for people; "" for None.
std::string_view language_title(MissionLanguage language);

// ".coral" or ".pl"; "" for None.
std::string_view mission_extension(MissionLanguage language);

}  // namespace strata::core

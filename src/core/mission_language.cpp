#include "core/mission_language.h"

#include <filesystem>

namespace strata::core {

MissionLanguage mission_language(std::string_view path) {
  const std::filesystem::path extension = std::filesystem::path(path).extension();
  if (extension == ".coral") return MissionLanguage::Coral;
  if (extension == ".pl") return MissionLanguage::Prolog;
  return MissionLanguage::None;
}

std::string_view language_key(MissionLanguage language) {
  switch (language) {
    case MissionLanguage::Coral: return "coral";
    case MissionLanguage::Prolog: return "prolog";
    case MissionLanguage::None: break;
  }
  return "";
}

std::string_view language_title(MissionLanguage language) {
  switch (language) {
    case MissionLanguage::Coral: return "CORAL";
    case MissionLanguage::Prolog: return "PROLOG";
    case MissionLanguage::None: break;
  }
  return "";
}

std::string_view mission_extension(MissionLanguage language) {
  switch (language) {
    case MissionLanguage::Coral: return ".coral";
    case MissionLanguage::Prolog: return ".pl";
    case MissionLanguage::None: break;
  }
  return "";
}

}  // namespace strata::core

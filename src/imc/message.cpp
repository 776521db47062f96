#include "imc/message.h"

namespace strata::imc {

std::uint16_t id_of(const Message& m) {
  return std::visit([](const auto& message) { return std::remove_cvref_t<decltype(message)>::kId; }, m);
}

std::string_view name_of(std::uint16_t id) {
  switch (id) {
    // clang-format off
#define IMC_MESSAGE(Name, id) case id: return Name::kName;
#include "imc/messages.def"
    // clang-format on
    default: return {};
  }
}

bool is_known(std::uint16_t id) { return !name_of(id).empty(); }

}  // namespace strata::imc

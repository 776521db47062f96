#pragma once
// IMC 5.4.x messages as plain structs, one per message of messages.def,
// named as IMC names them, fields by IMC's abbrev in wire order. Each struct
// has `static constexpr std::uint16_t kId` and `std::string_view kName`,
// and its enumerations and bits as constants (see messages.def for the
// names). Values compare with ==; copies are deep (an Inline owns its
// message).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace strata::imc {

inline constexpr std::uint16_t kSync = 0xFE54;        // IMC 5.4.x, little-endian
inline constexpr std::uint16_t kNullId = 0xFFFF;      // inline "no message"; also broadcast system
inline constexpr std::uint16_t kAnyVehicle = 0xFFF0;  // DUNE accepts PlanControl addressed here
inline constexpr std::uint8_t kAnyEntity = 0xFF;
inline constexpr std::size_t kHeaderBytes = 20, kFooterBytes = 2;
// Inline messages nest at most this deep below the packet's message (a
// message-list's element is one level, as an inline field is).
inline constexpr std::size_t kMaxDepth = 8;
// Inline messages one packet may hold in all, at any depth (list elements
// included): past it the packet is dropped (Drop::TooDeep), so that decoding
// a datagram allocates a bounded number of messages.
inline constexpr std::size_t kMaxInlineMessages = 1024;
// Strata's own convention on top of IMC (docs/imc.md, "Lockstep"): a vehicle
// whose Announce lists this service ends each cycle with a Heartbeat and
// waits for its controller's, stamped with that cycle's time; a Strata link
// that hears it sends one when it has done with the cycle.
inline constexpr std::string_view kLockstepService = "strata://lockstep";

// The wire's types, as messages.def names them.
namespace wire {
using u8 = std::uint8_t;
using u16 = std::uint16_t;
using u32 = std::uint32_t;
using u64 = std::uint64_t;
using i8 = std::int8_t;
using i16 = std::int16_t;
using i32 = std::int32_t;
using i64 = std::int64_t;
using fp32 = float;
using fp64 = double;
}  // namespace wire

namespace detail {
struct MessageBox;
}

// An inline message field of any type: a copyable value that owns one
// imc::Message, or nothing (empty: on the wire, the null id 0xFFFF).
class Inline {
 public:
  Inline() = default;
  // From any message struct, or a Message.
  template <typename T, typename = std::enable_if_t<!std::is_same_v<std::remove_cvref_t<T>, Inline>>>
  Inline(T message);  // NOLINT: implicit by design, `plan.arg = spec;`
  Inline(const Inline& other);
  Inline(Inline&& other) noexcept;
  Inline& operator=(const Inline& other);
  Inline& operator=(Inline&& other) noexcept;
  ~Inline();

  bool empty() const { return box_ == nullptr; }
  // The message's id, kNullId when empty.
  std::uint16_t id() const;
  // The message, nullptr when empty.
  const auto* get() const;
  // The message as a T, nullptr when empty or another type.
  template <typename T>
  const T* get_if() const;

  friend bool operator==(const Inline& a, const Inline& b);

 private:
  std::unique_ptr<detail::MessageBox> box_;
};

#define IMC_MESSAGE(Name, id)                \
  struct Name {                              \
    static constexpr std::uint16_t kId = id; \
    static constexpr std::string_view kName = #Name;
#define IMC_CONST(type, name, value) static constexpr wire::type name = value;
#define IMC_FIELD(type, name) wire::type name{};
#define IMC_TEXT(name) std::string name;
#define IMC_RAW(name) std::vector<std::uint8_t> name;
#define IMC_MSG(Type, name) std::optional<Type> name;
#define IMC_ANY(name) Inline name;
#define IMC_LIST(Type, name) std::vector<Type> name;
#define IMC_ANY_LIST(name) std::vector<Inline> name;
#define IMC_END(Name)                                         \
  friend bool operator==(const Name&, const Name&) = default; \
  }                                                           \
  ;
#include "imc/messages.def"

namespace detail {
template <typename First, typename... Rest>
struct VariantOfRest {
  using type = std::variant<Rest...>;
};
}  // namespace detail

// Every message of messages.def, in its order.
using Message = detail::VariantOfRest<void
#define IMC_MESSAGE(Name, id) , Name
#include "imc/messages.def"
                                      >::type;

std::uint16_t id_of(const Message& m);
// The message's name ("EstimatedState"), "" when the id is unknown.
std::string_view name_of(std::uint16_t id);
bool is_known(std::uint16_t id);

namespace detail {
struct MessageBox {
  Message value;
};
}  // namespace detail

template <typename T, typename>
Inline::Inline(T message)
    : box_(std::make_unique<detail::MessageBox>(detail::MessageBox{Message(std::move(message))})) {}
inline Inline::Inline(const Inline& other)
    : box_(other.box_ ? std::make_unique<detail::MessageBox>(*other.box_) : nullptr) {}
inline Inline::Inline(Inline&& other) noexcept = default;
inline Inline& Inline::operator=(const Inline& other) {
  if (this != &other) box_ = other.box_ ? std::make_unique<detail::MessageBox>(*other.box_) : nullptr;
  return *this;
}
inline Inline& Inline::operator=(Inline&& other) noexcept = default;
inline Inline::~Inline() = default;

inline std::uint16_t Inline::id() const { return box_ ? id_of(box_->value) : kNullId; }
inline const auto* Inline::get() const { return box_ ? &box_->value : nullptr; }
template <typename T>
const T* Inline::get_if() const {
  return box_ ? std::get_if<T>(&box_->value) : nullptr;
}
inline bool operator==(const Inline& a, const Inline& b) {
  if (a.empty() || b.empty()) return a.empty() == b.empty();
  return a.box_->value == b.box_->value;
}

}  // namespace strata::imc

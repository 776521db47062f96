#include "imc/codec.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

namespace strata::imc {

// The wire is little-endian and so are the hosts Strata builds for (x86-64,
// arm64): numbers are copied as they are.
static_assert(std::endian::native == std::endian::little, "the IMC codec assumes a little-endian host");

namespace {

// CRC-16-IBM, reflected (polynomial 0xA001), initial 0: a byte at a time
// from a table built at compile time.
constexpr std::array<std::uint16_t, 256> make_crc_table() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned i = 0; i < 256; ++i) {
    unsigned crc = i;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) ? (crc >> 1) ^ 0xA001u : crc >> 1;
    table[i] = static_cast<std::uint16_t>(crc);
  }
  return table;
}
constexpr std::array<std::uint16_t, 256> kCrcTable = make_crc_table();

std::uint16_t crc16(const std::uint8_t* bytes, std::size_t n) {
  unsigned crc = 0;
  for (std::size_t i = 0; i < n; ++i) crc = (crc >> 8) ^ kCrcTable[(crc ^ bytes[i]) & 0xFFu];
  return static_cast<std::uint16_t>(crc);
}

template <typename T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

constexpr std::size_t kMaxLength = std::numeric_limits<std::uint16_t>::max();

// ---- writing ------------------------------------------------------------------

// Appends fields to a datagram; remembers the first thing that cannot be
// encoded and then writes nothing more of consequence.
class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}

  const std::string& error() const { return error_; }

  template <typename T>
  requires std::is_arithmetic_v<T>
  void put(T value) {
    const std::size_t at = out_.size();
    out_.resize(at + sizeof value);
    std::memcpy(out_.data() + at, &value, sizeof value);
  }
  void put(const std::string& text) { put_bytes(text.data(), text.size(), "text"); }
  void put(const std::vector<std::uint8_t>& raw) { put_bytes(raw.data(), raw.size(), "rawdata"); }
  template <typename T>
  void put(const std::optional<T>& message) {
    if (!message) {
      put(kNullId);
      return;
    }
    put(T::kId);
    nested(*message);
  }
  void put(const Inline& message);
  template <typename T>
  void put(const std::vector<T>& list) {
    if (!count(list.size())) return;
    for (const T& element : list) put_element(element);
  }

  // The payload of one message at the current depth.
  void payload(const Message& m);

 private:
  template <typename T>
  void put_element(const T& element) {
    if constexpr (std::is_same_v<T, Inline>) {
      put(element);
    } else {
      put(T::kId);
      nested(element);
    }
  }
  bool count(std::size_t n) {
    if (n > kMaxLength) return fail("a message list of more than 65535 messages");
    put(static_cast<std::uint16_t>(n));
    return true;
  }
  void put_bytes(const void* data, std::size_t n, const char* what) {
    if (n > kMaxLength) {
      fail(std::string(what) + " of more than 65535 bytes");
      return;
    }
    put(static_cast<std::uint16_t>(n));
    const std::size_t at = out_.size();
    out_.resize(at + n);
    if (n > 0) std::memcpy(out_.data() + at, data, n);
  }
  template <typename T>
  void nested(const T& message);
  bool enter();
  bool fail(std::string what) {
    if (error_.empty()) error_ = std::move(what);
    return false;
  }

  std::vector<std::uint8_t>& out_;
  std::string error_;
  std::size_t depth_ = 0;
  std::size_t inlines_ = 0;  // inline messages written, at any depth (kMaxInlineMessages)
};

// ---- reading ------------------------------------------------------------------

// Reads fields from a payload; the first failure's reason is kept and every
// later read fails.
class Reader {
 public:
  Reader(const std::uint8_t* begin, const std::uint8_t* end) : at_(begin), end_(end) {}

  bool at_end() const { return at_ == end_; }
  Drop failure() const { return failure_; }
  bool fail(Drop why) {
    failure_ = why;
    at_ = end_;
    return false;
  }

  template <typename T>
  requires std::is_arithmetic_v<T>
  bool get(T& value) {
    if (left() < sizeof value) return fail(Drop::BadField);
    value = load<T>(at_);
    at_ += sizeof value;
    return true;
  }
  bool get(std::string& text) {
    std::uint16_t n = 0;
    if (!get(n)) return false;
    if (left() < n) return fail(Drop::BadField);
    text.assign(reinterpret_cast<const char*>(at_), n);
    at_ += n;
    return true;
  }
  bool get(std::vector<std::uint8_t>& raw) {
    std::uint16_t n = 0;
    if (!get(n)) return false;
    if (left() < n) return fail(Drop::BadField);
    raw.assign(at_, at_ + n);
    at_ += n;
    return true;
  }
  template <typename T>
  bool get(std::optional<T>& message) {
    std::uint16_t id = 0;
    if (!get(id)) return false;
    if (id == kNullId) {
      message.reset();
      return true;
    }
    if (id != T::kId) return fail(is_known(id) ? Drop::BadField : Drop::UnknownId);
    return nested(message.emplace());
  }
  bool get(Inline& message);
  template <typename T>
  bool get(std::vector<T>& list) {
    std::uint16_t n = 0;
    if (!get(n)) return false;
    // Each element takes at least its id's two bytes: a count the bytes
    // left cannot hold is refused before anything is allocated for it.
    if (left() / 2 < n) return fail(Drop::BadField);
    list.clear();
    for (std::uint16_t i = 0; i < n; ++i) {
      if (!get_element(list.emplace_back())) return false;
    }
    return true;
  }

  // The payload of the message with this id at the current depth, into
  // `out` (any previous value replaced).
  bool payload(std::uint16_t id, Message& out);

 private:
  std::size_t left() const { return static_cast<std::size_t>(end_ - at_); }
  template <typename T>
  bool get_element(T& element) {
    if constexpr (std::is_same_v<T, Inline>) {
      return get(element);
    } else {
      std::uint16_t id = 0;
      if (!get(id)) return false;
      if (id != T::kId) return fail(is_known(id) ? Drop::BadField : Drop::UnknownId);
      return nested(element);
    }
  }
  template <typename T>
  bool nested(T& message);

  const std::uint8_t* at_;
  const std::uint8_t* end_;
  Drop failure_ = Drop::BadField;
  std::size_t depth_ = 0;
  std::size_t inlines_ = 0;  // inline messages read, at any depth
};

// ---- per message, from messages.def ---------------------------------------------

#define IMC_MESSAGE(Name, id)                          \
  void write_payload(Writer& out_, const Name& msg_) { \
    (void)out_;                                        \
    (void)msg_;
#define IMC_FIELD(type, name) out_.put(msg_.name);
#define IMC_TEXT(name) out_.put(msg_.name);
#define IMC_RAW(name) out_.put(msg_.name);
#define IMC_MSG(Type, name) out_.put(msg_.name);
#define IMC_ANY(name) out_.put(msg_.name);
#define IMC_LIST(Type, name) out_.put(msg_.name);
#define IMC_ANY_LIST(name) out_.put(msg_.name);
#define IMC_END(Name) }
#include "imc/messages.def"

// Name is a type in a declaration, which parentheses would break.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define IMC_MESSAGE(Name, id)                  \
  bool read_payload(Reader& in_, Name& msg_) { \
    (void)in_;                                 \
    (void)msg_;                                \
    return true
// NOLINTEND(bugprone-macro-parentheses)
#define IMC_FIELD(type, name) &&in_.get(msg_.name)
#define IMC_TEXT(name) &&in_.get(msg_.name)
#define IMC_RAW(name) &&in_.get(msg_.name)
#define IMC_MSG(Type, name) &&in_.get(msg_.name)
#define IMC_ANY(name) &&in_.get(msg_.name)
#define IMC_LIST(Type, name) &&in_.get(msg_.name)
#define IMC_ANY_LIST(name) &&in_.get(msg_.name)
#define IMC_END(Name) \
  ;                   \
  }
#include "imc/messages.def"

// ---- the recursive parts --------------------------------------------------------

void Writer::payload(const Message& m) {
  std::visit([this](const auto& message) { write_payload(*this, message); }, m);
}

// One more inline message below this depth, or why it cannot be written
// (what decode() would drop).
bool Writer::enter() {
  if (depth_ == kMaxDepth) {
    fail("inline messages nested deeper than 8");
    return false;
  }
  if (++inlines_ > kMaxInlineMessages) {
    fail("more than 1024 inline messages in one packet");
    return false;
  }
  return true;
}

template <typename T>
void Writer::nested(const T& message) {
  if (!enter()) return;
  ++depth_;
  write_payload(*this, message);
  --depth_;
}

void Writer::put(const Inline& message) {
  put(message.id());
  if (const Message* m = message.get()) {
    if (!enter()) return;
    ++depth_;
    payload(*m);
    --depth_;
  }
}

bool Reader::payload(std::uint16_t id, Message& out) {
  switch (id) {
    // clang-format off
#define IMC_MESSAGE(Name, id) case id: return read_payload(*this, out.emplace<Name>());
#include "imc/messages.def"
    // clang-format on
    default: return fail(Drop::UnknownId);
  }
}

template <typename T>
bool Reader::nested(T& message) {
  if (depth_ == kMaxDepth) return fail(Drop::TooDeep);
  if (++inlines_ > kMaxInlineMessages) return fail(Drop::TooDeep);
  ++depth_;
  const bool ok = read_payload(*this, message);
  --depth_;
  return ok;
}

bool Reader::get(Inline& message) {
  std::uint16_t id = 0;
  if (!get(id)) return false;
  if (id == kNullId) {
    message = Inline();
    return true;
  }
  if (!is_known(id)) return fail(Drop::UnknownId);
  if (depth_ == kMaxDepth) return fail(Drop::TooDeep);
  // Each inline message is an allocation of a whole Message: a 64 KiB
  // datagram of two-byte Heartbeats in a list would be 32,000 of them.
  if (++inlines_ > kMaxInlineMessages) return fail(Drop::TooDeep);
  Message m;
  ++depth_;
  const bool ok = payload(id, m);
  --depth_;
  if (!ok) return false;
  message = Inline(std::move(m));
  return true;
}

// ---- the header -----------------------------------------------------------------

void write_header(std::uint8_t* p, const Header& h) {
  auto put = [&p](auto value) {
    std::memcpy(p, &value, sizeof value);
    p += sizeof value;
  };
  put(kSync);
  put(h.mgid);
  put(h.size);
  put(h.timestamp);
  put(h.src);
  put(h.src_ent);
  put(h.dst);
  put(h.dst_ent);
}

Header read_header(const std::uint8_t* p) {
  Header h;
  h.mgid = load<std::uint16_t>(p + 2);
  h.size = load<std::uint16_t>(p + 4);
  h.timestamp = load<double>(p + 6);
  h.src = load<std::uint16_t>(p + 14);
  h.src_ent = p[16];
  h.dst = load<std::uint16_t>(p + 17);
  h.dst_ent = p[19];
  return h;
}

}  // namespace

core::Result<std::vector<std::uint8_t>> encode(const Packet& packet) {
  std::vector<std::uint8_t> out(kHeaderBytes);
  out.reserve(128);
  Writer writer(out);
  writer.payload(packet.message);
  if (!writer.error().empty()) return core::make_error(core::ErrorCode::InvalidInput, "imc: " + writer.error());
  if (out.size() + kFooterBytes > kMaxPacketBytes) {
    return core::make_error(core::ErrorCode::InvalidInput, "imc: a packet of more than 65535 bytes");
  }
  Header header = packet.header;
  header.mgid = id_of(packet.message);
  header.size = static_cast<std::uint16_t>(out.size() - kHeaderBytes);
  write_header(out.data(), header);
  const std::uint16_t crc = crc16(out.data(), out.size());
  out.push_back(static_cast<std::uint8_t>(crc & 0xFFu));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

std::string_view drop_name(Drop d) {
  switch (d) {
    case Drop::Truncated: return "truncated";
    case Drop::BadSync: return "bad_sync";
    case Drop::BadSize: return "bad_size";
    case Drop::BadCrc: return "bad_crc";
    case Drop::UnknownId: return "unknown_id";
    case Drop::BadField: return "bad_field";
    case Drop::TooDeep: return "too_deep";
    case Drop::Filtered: return "filtered";
  }
  return "unknown";
}

std::optional<Header> peek_header(std::span<const std::uint8_t> datagram) {
  if (datagram.size() < kHeaderBytes || load<std::uint16_t>(datagram.data()) != kSync) return std::nullopt;
  return read_header(datagram.data());
}

std::variant<Packet, Drop> decode(std::span<const std::uint8_t> datagram) {
  if (datagram.size() < kHeaderBytes + kFooterBytes) return Drop::Truncated;
  const std::uint8_t* p = datagram.data();
  if (load<std::uint16_t>(p) != kSync) return Drop::BadSync;
  if (datagram.size() > kMaxPacketBytes) return Drop::BadSize;
  Packet packet;
  packet.header = read_header(p);
  const std::size_t payload_bytes = datagram.size() - kHeaderBytes - kFooterBytes;
  if (packet.header.size > payload_bytes) return Drop::Truncated;
  if (packet.header.size < payload_bytes) return Drop::BadSize;
  const std::size_t crc_at = kHeaderBytes + payload_bytes;
  if (crc16(p, crc_at) != load<std::uint16_t>(p + crc_at)) return Drop::BadCrc;
  if (!is_known(packet.header.mgid)) return Drop::UnknownId;
  Reader reader(p + kHeaderBytes, p + crc_at);
  if (!reader.payload(packet.header.mgid, packet.message)) return reader.failure();
  if (!reader.at_end()) return Drop::BadField;
  return packet;
}

std::uint64_t DropCounts::total() const {
  std::uint64_t n = 0;
  for (std::uint64_t c : by_reason) n += c;
  return n;
}

void DropCounts::add(Drop d) { ++by_reason[static_cast<std::size_t>(d)]; }

std::string DropCounts::summary() const {
  std::array<std::size_t, kDropReasons> order{};
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [this](std::size_t a, std::size_t b) { return by_reason[a] > by_reason[b]; });
  std::string out;
  for (std::size_t i : order) {
    if (by_reason[i] == 0) break;
    if (!out.empty()) out += ", ";
    out += std::to_string(by_reason[i]);
    out += ' ';
    out += drop_name(static_cast<Drop>(i));
  }
  return out.empty() ? "none" : out;
}

}  // namespace strata::imc

#include "strategic/coral_catalogue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coral/compiler.h"
#include "tactical/render.h"

namespace strata::strategic {
namespace {

using tactical::Catalogue;
using tactical::Value;

const std::string kSourceDir = STRATA_SOURCE_DIR;

// Diagnostics of compiling main.coral = text against the built-in catalogue,
// as "LINE:COL Kind" strings.
struct Checked {
  core::SourceManager sources;
  core::DiagnosticSink sink;
  std::optional<coral::Program> program;
  std::vector<std::string> kinds() const {
    std::vector<std::string> out;
    for (const auto& d : sink.diagnostics()) {
      auto lc = sources.line_col(d.span.file, d.span.offset);
      out.push_back(std::to_string(lc.line) + ":" + std::to_string(lc.col) + " " +
                    std::string(core::kind_name(d.kind)));
    }
    return out;
  }
};

std::unique_ptr<Checked> check_text(const std::string& text) {
  auto c = std::make_unique<Checked>();
  coral::MemoryFileProvider files;
  files.add("main.coral", text);
  c->program = coral::compile_file("main.coral", files, c->sources, c->sink, coral_check_options(Catalogue::builtin()));
  c->sink.sort();
  return c;
}

// A call rendered with the built-in catalogue: the line sent to the vehicle.
std::string text_of(std::string_view name, std::vector<Value> args) {
  const tactical::Primitive* p = Catalogue::builtin().find(name);
  EXPECT_TRUE(p) << name;
  if (!p) return "";
  auto r = tactical::render(*p, args, nullptr);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value().text() : "";
}

TEST(Catalogue, CheckOptionsAcceptTheTankMission) {
  coral::DiskFileProvider disk;
  core::SourceManager sources;
  core::DiagnosticSink sink;
  auto program = coral::compile_file(kSourceDir + "/missions/tank/tank.coral", disk, sources, sink,
                                     coral_check_options(Catalogue::builtin()));
  EXPECT_TRUE(program);
  EXPECT_FALSE(sink.has_errors());
  EXPECT_EQ(0u, sink.warning_count());
}

TEST(Catalogue, CheckOptionsRejectAMisspelledPrimitiveWithASuggestion) {
  auto c = check_text(
      "net n { place s = 1, a, b; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(ASK, depth_reachd, a, b) } }\n"
      "  transition t2 { wait { a } signal { e } }\n"
      "  transition t3 { wait { b } signal { e } } }");
  EXPECT_EQ((std::vector<std::string>{"2:51 UnknownPrimitive"}), c->kinds());
  ASSERT_EQ(1u, c->sink.diagnostics().size());
  ASSERT_EQ(1u, c->sink.diagnostics()[0].notes.size());
  EXPECT_EQ("did you mean 'depth_reached'?", c->sink.diagnostics()[0].notes[0].message);
  EXPECT_FALSE(c->program);
}

TEST(Catalogue, CheckOptionsRejectAMissingArgument) {
  auto c = check_text(
      "net n { place s = 1; exit e;\n"
      "  transition t { wait { s } action { TACTIC(EXEC, sleep, e) } } }");
  EXPECT_EQ((std::vector<std::string>{"2:51 PrimitiveArity"}), c->kinds());
  EXPECT_EQ("'sleep' takes 1 argument, but 0 given", c->sink.diagnostics()[0].message);
}

TEST(Catalogue, CheckOptionsRejectAWrongKind) {
  auto c = check_text(
      "net n { place s = 1; exit e;\n"
      "  transition t { wait { s } action { TACTIC(EXEC, depth_reached, e) } } }");
  EXPECT_EQ((std::vector<std::string>{"2:51 TacticArguments"}), c->kinds());
}

TEST(Catalogue, CheckOptionsOutliveTheCatalogue) {
  coral::CheckOptions options;
  std::size_t primitives = 0;
  {
    auto c = Catalogue::load(kSourceDir + "/config/primitives.toml");
    ASSERT_TRUE(c.ok());
    primitives = c.value().all().size();
    options = coral_check_options(c.value());
  }
  auto sig = options.primitive("sleep");
  ASSERT_TRUE(sig);
  EXPECT_EQ(coral::ast::TacticType::Exec, sig->kind);
  EXPECT_EQ(1u, sig->min_args);
  EXPECT_EQ(1u, sig->max_args);
  EXPECT_FALSE(options.primitive("nope"));
  EXPECT_EQ(primitives, options.primitive_names.size());
}

TEST(Catalogue, OptionalArgumentsWidenTheSignature) {
  auto c = Catalogue::parse(
      "[[primitive]]\nname = \"goto_depth\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 5\n"
      "message = \"exec goto_depth {depth_m} {speed}\"\n"
      "args = [{ name = \"depth_m\", type = \"number\", unit = \"m\", min = 0 },\n"
      "        { name = \"speed\", type = \"number\", unit = \"m/s\", default = 0.2 }]\n",
      "cat.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  auto sig = coral_check_options(c.value()).primitive("goto_depth");
  ASSERT_TRUE(sig);
  EXPECT_EQ(1u, sig->min_args);
  EXPECT_EQ(2u, sig->max_args);
}

TEST(Render, CoralLiteralsBecomeValues) {
  coral::ast::Literal one{coral::ast::Literal::Kind::Integer, "1", "1", {}};
  coral::ast::Literal one_f{coral::ast::Literal::Kind::Float, "1.0", "1.0", {}};
  coral::ast::Literal text{coral::ast::Literal::Kind::String, "\"a\\\"b\"", "a\"b", {}};
  EXPECT_EQ(Value::of(1.0), value_of(one));
  EXPECT_EQ(Value::of(1.0), value_of(one_f));
  EXPECT_EQ(Value::of("a\"b"), value_of(text));
  // Same call written two ways, same message.
  EXPECT_EQ(text_of("sleep", {value_of(one)}), text_of("sleep", {value_of(one_f)}));
  coral::ast::Literal junk{coral::ast::Literal::Kind::Float, "1.x", "1.x", {}};
  EXPECT_TRUE(std::isnan(value_of(junk).number));
}

}  // namespace
}  // namespace strata::strategic

#include "protocol/framer.h"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

namespace strata::protocol {
namespace {

namespace gen = rc::gen;

// Frames as one string: lines in [..], too-long ones as <too_long:N bytes kept>.
std::string show(const std::vector<Frame>& frames) {
  std::string out;
  for (const Frame& f : frames) {
    out += f.too_long ? "<too_long:" + std::to_string(f.line.size()) + ">" : "[" + f.line + "]";
  }
  return out;
}

std::vector<Frame> feed_all(LineFramer& framer, const std::vector<std::string>& chunks) {
  std::vector<Frame> out;
  for (const std::string& c : chunks) {
    for (Frame& f : framer.feed(c)) out.push_back(std::move(f));
  }
  return out;
}

TEST(Framer, SeveralLinesInOneChunk) {
  LineFramer f;
  EXPECT_EQ("[ping 1][ping 2][]", show(f.feed("ping 1\nping 2\n\n")));
  EXPECT_EQ(0u, f.pending_bytes());
}

TEST(Framer, LinesSplitAcrossChunks) {
  LineFramer f;
  EXPECT_EQ("", show(f.feed("exec 7 sl")));
  EXPECT_EQ(9u, f.pending_bytes());
  EXPECT_EQ("", show(f.feed("eep 1")));
  EXPECT_EQ("[exec 7 sleep 1][pi]", show(f.feed("\npi\n")));
  EXPECT_EQ("", show(f.feed("")));
}

TEST(Framer, CrlfIsOneTerminatorAndALoneCrIsKept) {
  LineFramer f;
  EXPECT_EQ("[ping 1]", show(f.feed("ping 1\r\nping 2\r")));
  EXPECT_EQ("", show(f.feed("")));
  EXPECT_EQ("[ping 2]", show(f.feed("\n")));    // "\r" then "\n" in separate chunks
  EXPECT_EQ("[a\rb]", show(f.feed("a\rb\n")));  // left for the decoder to reject
}

TEST(Framer, OverlongLineIsReportedOnceAndTheNextLineStillRead) {
  LineFramer f;
  const std::string big(kMaxLineBytes, 'x');
  std::vector<Frame> frames = f.feed(big);
  EXPECT_EQ("<too_long:1023>", show(frames));
  EXPECT_EQ(std::string(kMaxLineBytes - 1, 'x'), frames[0].line);
  EXPECT_TRUE(f.discarding());
  EXPECT_EQ("", show(f.feed(big)));
  EXPECT_EQ("", show(f.feed(big + big)));
  EXPECT_EQ("[ping 2]", show(f.feed("yyy\nping 2\n")));
  EXPECT_FALSE(f.discarding());
}

TEST(Framer, TheLimitCountsTheTerminator) {
  LineFramer f;
  const std::string fits(kMaxLineBytes - 1, 'a');
  EXPECT_EQ("[" + fits + "]", show(f.feed(fits + "\n")));
  EXPECT_EQ("[" + fits.substr(1) + "]", show(f.feed(fits.substr(1) + "\r\n")));
  EXPECT_EQ("<too_long:1023>", show(f.feed(fits + "\r\n")));
  EXPECT_EQ("<too_long:1023>[ok]", show(f.feed(fits + "b\nok\n")));
  // Known too long only when the byte after the 1023rd arrives.
  EXPECT_EQ("", show(f.feed(fits)));
  EXPECT_EQ(kMaxLineBytes - 1, f.pending_bytes());
  EXPECT_EQ("<too_long:1023>", show(f.feed("c")));
  EXPECT_EQ("[]", show(f.feed("\n\n")));
}

TEST(Framer, ResetDropsThePartialLine) {
  LineFramer f;
  EXPECT_EQ("", show(f.feed("half")));
  f.reset();
  EXPECT_EQ("[whole]", show(f.feed("whole\n")));
}

// What the framer must do, written the obvious way over the whole stream.
std::vector<Frame> reference_frames(const std::string& stream) {
  std::vector<Frame> out;
  std::size_t start = 0;
  while (true) {
    std::size_t nl = stream.find('\n', start);
    std::size_t end = nl == std::string::npos ? stream.size() : nl;
    std::string line = stream.substr(start, end - start);
    if (line.size() + 1 > kMaxLineBytes) {
      out.push_back(Frame{line.substr(0, kMaxLineBytes - 1), true});
    } else if (nl != std::string::npos) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      out.push_back(Frame{line, false});
    }
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  return out;
}

rc::Gen<std::string> streams() {
  // Lines of all sizes around the limit, with both terminators.
  auto line = gen::apply(
      [](std::size_t length, char fill, int terminator) {
        std::string l(length, fill);
        if (terminator == 1) l += '\n';
        if (terminator == 2) l += "\r\n";
        return l;
      },
      gen::oneOf(gen::inRange<std::size_t>(0, 20), gen::inRange<std::size_t>(kMaxLineBytes - 4, kMaxLineBytes + 4),
                 gen::inRange<std::size_t>(0, 3 * kMaxLineBytes)),
      gen::element('a', '\r', ' '), gen::inRange(0, 3));
  return gen::map(gen::container<std::vector<std::string>>(line), [](std::vector<std::string> ls) {
    std::string s;
    for (const std::string& l : ls) s += l;
    return s;
  });
}

RC_GTEST_PROP(Framer, AnyChunkingGivesTheSameFrames, ()) {
  const std::string stream = *streams();
  const std::vector<std::size_t> cuts =
      *gen::container<std::vector<std::size_t>>(gen::inRange<std::size_t>(0, stream.size() + 1));
  std::vector<std::string> chunks;
  std::size_t at = 0;
  std::vector<std::size_t> sorted = cuts;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t c : sorted) {
    chunks.push_back(stream.substr(at, c - at));
    at = c;
  }
  chunks.push_back(stream.substr(at));

  LineFramer whole;
  const std::vector<Frame> expected = whole.feed(stream);
  RC_ASSERT(expected == reference_frames(stream));
  LineFramer chunked;
  RC_ASSERT(feed_all(chunked, chunks) == expected);
  RC_ASSERT(chunked.pending_bytes() < kMaxLineBytes);
  RC_ASSERT(chunked.pending_bytes() == whole.pending_bytes());
}

}  // namespace
}  // namespace strata::protocol

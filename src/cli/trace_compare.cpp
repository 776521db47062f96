#include "cli/trace_compare.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/text.h"

namespace strata::cli {
namespace {

constexpr std::size_t kMaxCell = 46;

std::string cell_text(const TraceRow& row) {
  std::string text = row.call + " -> " + row.answer + (row.repeats > 1 ? fmt::format(" (x{})", row.repeats) : "");
  return text.size() > kMaxCell ? core::shorten(std::move(text), kMaxCell - 3, "...") : text;
}

std::string cell(const std::vector<TraceRow>& rows, std::size_t i, std::size_t width) {
  if (i >= rows.size()) return fmt::format("{:>7}  {:<{}}", "", "", width);
  return fmt::format("{:>7.1f}  {:<{}}", rows[i].sim_time_s, cell_text(rows[i]), width);
}

}  // namespace

bool TraceRow::operator==(const TraceRow& o) const {
  return call == o.call && answer == o.answer &&
         std::llround(sim_time_s * 1000.0) == std::llround(o.sim_time_s * 1000.0);
}

TraceRow trace_row(const tactical::CallRecord& r) {
  TraceRow row;
  row.verb = r.verb;
  row.guard = !r.guard.empty();
  const bool to_vehicle = r.verb && *r.verb != core::CallVerb::Report;
  row.call = to_vehicle ? r.message : fmt::format("{} \"{}\"", r.primitive, r.message);
  if (r.error) {
    if (r.message.empty()) row.call = r.primitive;
    row.answer = "error: " + r.error->message;
    row.failed = true;
  } else {
    row.answer.push_back(r.value && *r.value ? '1' : '0');
  }
  row.sim_time_s = r.sim_time_s;
  return row;
}

std::vector<TraceRow> trace_rows(const std::vector<tactical::CallRecord>& records) {
  std::vector<TraceRow> rows;
  rows.reserve(records.size());
  for (const auto& r : records) rows.push_back(trace_row(r));
  return rows;
}

std::vector<TraceRow> command_rows(const std::vector<TraceRow>& rows) {
  std::vector<TraceRow> out;
  for (const TraceRow& row : rows) {
    if (row.verb == core::CallVerb::Ask || row.guard) continue;
    TraceRow r = row;
    r.sim_time_s = 0.0;
    // Failed, either way: how it failed is in each vehicle's own words.
    if (r.failed) r.answer = "error";
    if (!out.empty() && out.back() == r) {
      ++out.back().repeats;
      continue;
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::optional<std::size_t> first_difference(const std::vector<TraceRow>& a, const std::vector<TraceRow>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!(a[i] == b[i])) return i;
  }
  if (a.size() != b.size()) return n;
  return std::nullopt;
}

std::string side_by_side(const std::vector<TraceRow>& a, const std::vector<TraceRow>& b,
                         const SideBySideOptions& options) {
  const std::size_t rows = std::max(a.size(), b.size());
  std::size_t width = std::max<std::size_t>(options.title_a.size(), 10);
  for (const auto& r : a) width = std::max(width, cell_text(r).size());
  const auto diff = first_difference(a, b);

  std::size_t from = 0, to = rows;
  if (options.context) {
    const std::size_t centre = diff ? *diff : rows;
    from = centre > *options.context ? centre - *options.context : 0;
    to = std::min(rows, centre + (diff ? *options.context + 1 : 0));
  }
  std::string out =
      fmt::format("{:>5} {:>7}  {:<{}}   {:>7}  {}\n", "#", "t (s)", options.title_a, width, "t (s)", options.title_b);
  if (from > 0) out += fmt::format("{:>5}  ({} identical calls before)\n", "...", from);
  for (std::size_t i = from; i < to; ++i) {
    const bool same = i < a.size() && i < b.size() && a[i] == b[i];
    out += fmt::format("{:>5}{}{} {} {}{}\n", i + 1, " ", cell(a, i, width), same ? "|" : "*", cell(b, i, width),
                       diff && i == *diff ? "  <<< first difference" : "");
  }
  if (to < rows) out += fmt::format("{:>5}  ({} more calls)\n", "...", rows - to);
  // Trailing spaces of the right column are noise.
  std::string trimmed;
  std::size_t start = 0;
  while (start < out.size()) {
    std::size_t end = out.find('\n', start);
    std::string line = out.substr(start, end - start);
    line.erase(line.find_last_not_of(' ') + 1);
    trimmed += line + "\n";
    start = end + 1;
  }
  return trimmed;
}

}  // namespace strata::cli

#include "campaign/report_html.h"

#include <algorithm>

#include <fmt/format.h>

namespace strata::campaign {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kStyle = R"(
body{font:14px/1.4 system-ui,sans-serif;margin:2em;color:#222;max-width:1200px}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:2em;border-bottom:1px solid #ccc}
table{border-collapse:collapse}td,th{padding:2px 6px;text-align:right}
th{font-weight:600}td.l,th.l{text-align:left}
.heat td.c{min-width:2.2em;text-align:center;font-size:12px;border:1px solid #fff}
.pass{color:#1a7f37}.fail{color:#c62828}.big{font-size:1.6em;font-weight:600;margin-right:1.5em}
code{background:#f3f3f3;padding:1px 4px;border-radius:3px;font-size:12px}
.failures td{vertical-align:top;border-top:1px solid #eee}
.muted{color:#777}
)";

std::string esc(const Json& j) { return html_escape(j.is_string() ? j.get<std::string>() : j.dump()); }

std::string number(const Json& j, const char* fmt_text = "{:.2f}") {
  return j.is_number() ? fmt::format(fmt::runtime(fmt_text), j.get<double>()) : "–";
}

// White (no failures) to red (all failed); grey: no case.
std::string heat_colour(std::uint64_t done, std::uint64_t failed) {
  if (done == 0) return "#eeeeee";
  const double f = static_cast<double>(failed) / static_cast<double>(done);
  if (failed == 0) return "#c8e6c9";
  const int g = static_cast<int>(220 - 170 * f), b = static_cast<int>(200 - 160 * f);
  return fmt::format("rgb(240,{},{})", g, b);
}

void counts(std::string& out, const Json& r) {
  const Json& c = r["cases"];
  out += fmt::format(
      "<p><span class=big>{} cases</span><span class='big pass'>{} passed</span>"
      "<span class='big {}'>{} failed</span></p>\n",
      c["done"].get<std::uint64_t>(), c["passed"].get<std::uint64_t>(),
      c["failed"].get<std::uint64_t>() > 0 ? "fail" : "muted", c["failed"].get<std::uint64_t>());
  if (r["interrupted"].get<bool>()) {
    out += fmt::format("<p class=fail>Interrupted: {} of the {} planned cases ran.</p>\n",
                       c["done"].get<std::uint64_t>(), c["planned"].get<std::uint64_t>());
  }
  const Json& t = r["timings"];
  out += fmt::format(
      "<p class=muted>{} worker(s), {:.1f} s of wall time, {:.1f} cases/s; a case took {:.1f} ms "
      "(median), {:.1f} ms at most. Outcomes: ",
      t["workers"].get<int>(), t["wall_s"].get<double>(), t["cases_per_s"].get<double>(),
      1000 * t["case_wall_p50_s"].get<double>(), 1000 * t["case_wall_max_s"].get<double>());
  bool first = true;
  for (const auto& [k, v] : r["outcomes"].items()) {
    out += fmt::format("{}{} {}", first ? "" : ", ", html_escape(k), v.get<std::uint64_t>());
    first = false;
  }
  out +=
      ".</p>\n<table><tr><th class=l>family</th><th class=l>fault</th><th class=l>expectations</th>"
      "<th>cases</th><th>failed</th></tr>\n";
  for (const Json& f : r["families"]) {
    out += fmt::format(
        "<tr><td class=l>{}</td><td class=l>{}</td><td class=l>{}</td><td>{}</td><td class={}>{}</td>"
        "</tr>\n",
        esc(f["name"]), esc(f["fault"]), esc(f["expect"]), f["done"].get<std::uint64_t>(),
        f["failed"].get<std::uint64_t>() ? "fail" : "pass", f["failed"].get<std::uint64_t>());
  }
  out += "</table>\n";
}

void heat_map(std::string& out, const Json& r) {
  out +=
      "<h2>Outcome matrix: family × injection time</h2>\n<p class=muted>Each cell: the cases failed of the cases "
      "run with the fault starting at that time (s); green: none failed, red: all failed. Hover for the outcomes."
      "</p>\n";
  for (const Json& row : r["matrix"]) {
    out += fmt::format("<h3>{} · {}</h3>\n<table class=heat><tr><th class=l>at_s</th>", esc(row["mission"]),
                       esc(row["family"]));
    for (const Json& c : row["cells"]) out += fmt::format("<th>{}</th>", esc(c["at_s"]));
    out += "</tr>\n<tr><td class=l>failed</td>";
    for (const Json& c : row["cells"]) {
      const auto done = c["done"].get<std::uint64_t>(), failed = c["failed"].get<std::uint64_t>();
      std::string title;
      for (const auto& [k, v] : c["outcomes"].items()) title += fmt::format("{} {}; ", k, v.get<std::uint64_t>());
      out += fmt::format("<td class=c style='background:{}' title='{}'>{}</td>", heat_colour(done, failed),
                         html_escape(title), done == 0 ? std::string("·") : fmt::format("{}/{}", failed, done));
    }
    out += "</tr></table>\n";
  }
}

// A bar chart of counts over [0, 20 * bin_s) with the limit drawn across.
std::string histogram_svg(const Json& h, double limit_s) {
  const auto& counts = h["counts"];
  const double bin = h["bin_s"].get<double>();
  std::uint64_t top = 1;
  for (const auto& c : counts) top = std::max(top, c.get<std::uint64_t>());
  const int w = 480, hgt = 160, pad = 30;
  const double bw = (w - 2.0 * pad) / static_cast<double>(counts.size());
  std::string s = fmt::format("<svg width='{}' height='{}' role='img'>", w, hgt + 30);
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double n = counts[i].get<double>();
    const double bh = n / static_cast<double>(top) * (hgt - 20);
    const bool over = bin * static_cast<double>(i) >= limit_s;
    s += fmt::format(
        "<rect x='{:.1f}' y='{:.1f}' width='{:.1f}' height='{:.1f}' fill='{}'><title>{:.2f}–{:.2f} s: "
        "{}</title></rect>",
        pad + bw * static_cast<double>(i), hgt - bh, bw - 1, bh, over ? "#e57373" : "#64b5f6",
        bin * static_cast<double>(i), bin * static_cast<double>(i + 1), counts[i].get<std::uint64_t>());
  }
  const double lx = pad + limit_s / bin * bw;
  s += fmt::format(
      "<line x1='{0:.1f}' x2='{0:.1f}' y1='0' y2='{1}' stroke='#c62828' stroke-dasharray='4 3'/>"
      "<text x='{2:.1f}' y='12' font-size='11' fill='#c62828' text-anchor='end'>T = {3} s</text>",
      lx, hgt, lx - 3, limit_s);
  s += fmt::format(
      "<line x1='{0}' x2='{1}' y1='{2}' y2='{2}' stroke='#999'/>"
      "<text x='{0}' y='{3}' font-size='11'>0 s</text><text x='{1}' y='{3}' font-size='11' "
      "text-anchor='end'>{4:.1f} s</text><text x='2' y='12' font-size='11'>{5}</text></svg>",
      pad, w - pad, hgt, hgt + 15, bin * static_cast<double>(counts.size()), top);
  return s;
}

void surfacing(std::string& out, const Json& r) {
  if (r["time_to_surface"].empty()) return;
  out +=
      "<h2>Time to surface after the fault</h2>\n<p class=muted>From the fault's start to the first depth reading "
      "at the surface (with the link gone: the vehicle's own log line, else its final state). Only families whose "
      "expectations set "
      "surface_within_s.</p>\n";
  for (const Json& s : r["time_to_surface"]) {
    out += fmt::format(
        "<h3>{} (T = {} s)</h3>\n<p>{} measured, {} over T, {} never seen at the surface. "
        "p50 {} s, p90 {} s, p99 {} s, max {} s.</p>\n",
        esc(s["family"]), s["limit_s"].get<double>(), s["measured"].get<std::uint64_t>(),
        s.value("over_limit", std::uint64_t{0}), s["never_surfaced"].get<std::uint64_t>(),
        number(s.value("p50_s", Json())), number(s.value("p90_s", Json())), number(s.value("p99_s", Json())),
        number(s.value("max_s", Json())));
    if (s.contains("histogram")) out += histogram_svg(s["histogram"], s["limit_s"].get<double>()) + "\n";
  }
}

void bounds(std::string& out, const Json& r) {
  if (!r.contains("bounds") || r["bounds"].empty()) return;
  out +=
      "<h2>Proven bounds</h2>\n<p class=muted>The timing analysis's worst case (<code>strata verify --bound</code>) "
      "beside the longest time measured from a fault to the bound's end. A case past the proven worst case is a "
      "failure of the analysis, not of the mission.</p>\n<table><tr><th>mission</th><th>family</th><th>bound</th>"
      "<th>proven</th><th>measured</th><th>longest</th><th>past the proof</th></tr>\n";
  for (const Json& b : r["bounds"]) {
    out += fmt::format(
        "<tr><td>{}</td><td>{}</td><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td{}>{}"
        "</td></tr>\n",
        esc(b["mission"]), esc(b["family"]), esc(b["bound"]),
        b["proven_s"].is_number() ? number(b["proven_s"]) + " s" : esc(b.value("note", Json("none"))),
        b["measured"].get<std::uint64_t>(), b["max_s"].is_number() ? number(b["max_s"]) + " s" : "-",
        b["exceeded"].get<std::uint64_t>() > 0 ? " class=fail" : "", b["exceeded"].get<std::uint64_t>());
  }
  out += "</table>\n";
}

void coverage(std::string& out, const Json& r) {
  out +=
      "<h2>Coverage</h2>\n<p class=muted>Across every case: the transitions that fired, and those no case "
      "fired (never exercised here — compare with what <code>strata verify</code> proves dead); the answers "
      "each ASK gave; the phase exits taken.</p>\n";
  for (const auto& [mission, c] : r["coverage"].items()) {
    out += fmt::format("<h3>{}</h3>\n", html_escape(mission));
    if (c.contains("transitions")) {
      out +=
          fmt::format("<p>{} of {} transitions fired.", c["transitions"].get<std::size_t>() - c["never_fired"].size(),
                      c["transitions"].get<std::size_t>());
      if (!c["never_fired"].empty()) {
        out += " Never fired: ";
        bool first = true;
        for (const auto& n : c["never_fired"]) {
          out += fmt::format("{}<code>{}</code>", first ? "" : " ", esc(n));
          first = false;
        }
      }
      out += "</p>\n";
    }
    for (const char* key : {"answers", "exits"}) {
      out += fmt::format("<p><b>{}</b>: ", key);
      bool first = true;
      for (const auto& [k, v] : c[key].items()) {
        out += fmt::format("{}<code>{}</code>&nbsp;{}", first ? "" : ", ", html_escape(k), v.get<std::uint64_t>());
        first = false;
      }
      out += first ? "none</p>\n" : "</p>\n";
    }
  }
}

void failures(std::string& out, const Json& r) {
  out += "<h2>Failing cases</h2>\n";
  if (r["failures"].empty()) {
    out += "<p class=pass>None.</p>\n";
    return;
  }
  out +=
      "<table class=failures><tr><th>case</th><th class=l>mission · family · fault</th><th class=l>outcome</th>"
      "<th class=l>failed expectations</th><th class=l>reproduce</th></tr>\n";
  for (const Json& f : r["failures"]) {
    const Json& in = f["inputs"];
    std::string fault;
    for (const auto& [k, v] : in["fault"].items())
      fault += fmt::format("{}={} ", k, v.is_string() ? v.get<std::string>() : v.dump());
    if (in.contains("params")) {
      for (const auto& [k, v] : in["params"].items()) fault += fmt::format("{}={} ", k, v.dump());
    }
    std::string checks;
    for (const Json& c : f["failed_checks"]) {
      checks += fmt::format("{}: {}{}<br>", esc(c["name"]), esc(c["figure"]),
                            c.contains("note") ? " — " + esc(c["note"]) : std::string());
    }
    std::string repro = fmt::format("<code>{}</code>", esc(f["repro"]));
    if (f.contains("repro_run")) repro += fmt::format("<br><code>{}</code>", esc(f["repro_run"]));
    if (f.contains("log")) repro += fmt::format("<br>log: <code>{}</code>", esc(f["log"]));
    if (f.contains("log_note")) repro += fmt::format("<br><span class=muted>{}</span>", esc(f["log_note"]));
    out += fmt::format(
        "<tr><td>{}</td><td class=l>{} · {} · {}seed={}</td><td class=l>{}<br><span class=muted>{}"
        "</span></td><td class=l>{}</td><td class=l>{}</td></tr>\n",
        f["index"].get<std::uint64_t>(), esc(in["mission"]), esc(in["family"]), html_escape(fault),
        in["seed"].get<std::uint64_t>(), esc(f["outcome"]), esc(f["reason"]), checks, repro);
  }
  out += "</table>\n";
  if (r["failures_not_listed"].get<std::uint64_t>() > 0) {
    out += fmt::format("<p>… and {} more (results.jsonl has them all).</p>\n",
                       r["failures_not_listed"].get<std::uint64_t>());
  }
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string report_html(const Json& r) {
  std::string out = fmt::format(
      "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>Campaign {}</title>"
      "<style>{}</style></head><body>\n<h1>Campaign {}</h1>\n<p class=muted>{}</p>\n",
      esc(r["campaign"]), kStyle, esc(r["campaign"]), esc(r["command"]));
  counts(out, r);
  failures(out, r);
  heat_map(out, r);
  surfacing(out, r);
  bounds(out, r);
  coverage(out, r);
  out += "</body></html>\n";
  return out;
}

}  // namespace strata::campaign

#pragma once
// report.html: the campaign's report as one self-contained page (inline CSS
// and SVG, no script, no external URL), drawn from report.json's content
// (Summary::to_json): the counts, the outcome matrix as a heat map, time to
// surface after a fault (percentiles and a histogram against the limit),
// coverage, and every listed failing case with its repro command.
#include <string>

#include <nlohmann/json.hpp>

namespace strata::campaign {

std::string report_html(const nlohmann::ordered_json& report);

// Text made safe inside HTML elements and attribute values.
std::string html_escape(const std::string& text);

}  // namespace strata::campaign

// report.md and the PNG plots, both rendered from the report.json object (one
// result, several renderings). The plots come from tools/plot_report.py run
// with Debian's /usr/bin/python3 (python3-matplotlib); when that is missing
// the report says so and the JSON and Markdown are still written.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rayverify {

// report.md, ready to paste into a pull request: the headline (does any
// target disagree with the exact answer), a compact table (one row per
// variant), the plots, then folded sections: every target's figures,
// stability, run time and far-sphere tables when the report has them, and how
// the report was made.
std::string render_markdown(const nlohmann::ordered_json& report);

// The headline and the compact table alone (`--summary-md FILE`, for a CI
// step summary).
std::string render_summary_markdown(const nlohmann::ordered_json& report);

struct plot_outcome {
    bool rendered = false;
    std::string message;             // why not, or what was drawn
    std::vector<std::string> files;  // PNG names written in the report directory
};

// Runs the plotting script on dir/report.json; never throws for a missing
// python or matplotlib (the outcome says so).
plot_outcome render_plots(const std::filesystem::path& dir);

// Writes dir/report.json, the plots (when `plots`; drawing takes seconds),
// then report.md, and rewrites report.json with report["plots"] (each file
// atomically). Returns the plot outcome.
plot_outcome write_report_bundle(const std::filesystem::path& dir, nlohmann::ordered_json report, bool plots);

}  // namespace rayverify

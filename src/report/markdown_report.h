// report.md and the PNG plots, both rendered from the report.json object (one
// result, several renderings). The plots come from tools/plot_report.py run
// with Debian's /usr/bin/python3 (python3-matplotlib); when that is missing
// the report says so and the JSON and Markdown are still written.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/outputs.h"

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

// How the plots are drawn: the image formats (png, svg, pdf; each plot once
// per format) and the accuracy-against-time plot's error measure,
// FIGURE:STATISTIC (an error figure's name and max, p99 or median).
struct plot_choices {
    std::vector<std::string> formats{"png"};
    std::string error_measure = "near_root_scaled_ulp:max";
};
// The choices from the command line's --plot-format and --error-measure
// (empty: the defaults); an unknown format, figure or statistic is an
// input_error naming the option.
plot_choices plot_choices_of(const std::vector<std::string>& formats, const std::string& error_measure);

// Runs the plotting script on dir/report.json; never throws for a missing
// python or matplotlib (the outcome says so).
plot_outcome render_plots(const std::filesystem::path& dir, const plot_choices& choices = {});

// A report directory's report.json, report.md and plots, as outputs of one
// run: the directory and both files are declared when this is constructed
// (before the work, so that a directory that cannot be written fails first);
// write() fills them. The plots are drawn from a copy of report.json in a
// staging directory and put in place with the rest on commit.
class report_bundle {
public:
    // `option` names the directory's option in messages (--report, -o).
    report_bundle(run_outputs& outputs, const std::filesystem::path& dir, const std::string& option);
    // report.json (with report["plots"] added) and report.md, after the plots
    // when `draw` (drawing takes seconds). Returns the plot outcome.
    plot_outcome write(nlohmann::ordered_json report, bool draw, const plot_choices& choices = {});
    const std::filesystem::path& dir() const { return dir_; }

private:
    run_outputs& outputs_;
    std::filesystem::path dir_;
    std::string option_;
    output_file& json_;
    output_file& markdown_;
};

}  // namespace rayverify

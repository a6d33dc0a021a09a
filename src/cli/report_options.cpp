// Options that choose how an audit's results are shown, shared by audit and merge.
#include "cli/commands.h"
#include "core/input_error.h"

namespace rayverify::cli {

void refuse_directory(const std::filesystem::path& path, const char* option) {
    std::error_code error;
    if (!path.empty() && std::filesystem::is_directory(path, error))
        throw input_error(path.string(), 0, option, "is a directory, expected a file to write");
}

void add_presentation_options(CLI::App* sub, audit_presentation& presentation) {
    sub->add_flag("--summary", presentation.summary,
                  "Print one line per variant family (its best and worst member) instead of the full table; "
                  "the report files are the same");
    sub->add_option("--summary-md", presentation.summary_md,
                    "Also write the headline and compact table of report.md to this file (for a CI step summary, "
                    "e.g. $GITHUB_STEP_SUMMARY)");
}

void open_presentation(audit_outputs& outputs, const audit_presentation& presentation) {
    if (presentation.summary_md.empty()) return;
    refuse_directory(presentation.summary_md, "--summary-md");
    outputs.summary_md.emplace(presentation.summary_md);
}

}  // namespace rayverify::cli

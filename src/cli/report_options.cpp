// Options shared by several commands: how an audit's results are shown (audit and merge), the figure
// tolerance (gate and diff).
#include "cli/commands.h"

namespace rayverify::cli {

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
    outputs.summary_md = &outputs.files.file(presentation.summary_md, "--summary-md");
}

void add_tolerance_option(CLI::App* sub, double& tolerance) {
    sub->add_option("--tolerance", tolerance,
                    "Relative difference below which two ULP figures are the same (last-digit noise); counts are "
                    "compared exactly")
        ->capture_default_str()
        ->check(finite_number(0, 0.5));
}

}  // namespace rayverify::cli

// What the CLI knows about where its output goes: whether a person watches
// stderr (progress), whether stdout may be coloured (a terminal, NO_COLOR
// unset, TERM not "dumb"), how wide the terminal is, and --quiet. Set once in
// main after parsing; read by the commands.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace rayverify::cli::terminal {

// Called by main: --quiet turns progress and notes off.
void configure(bool quiet);

bool quiet();
// Columns of the terminal on stdout (COLUMNS, else the tty's size, else 80), within [40, 200].
std::size_t width();

// ANSI colours for figures that got worse or failed (red) and better or passed
// (green), only when stdout is a terminal and NO_COLOR is not set.
std::string worse(std::string_view text);
std::string better(std::string_view text);

// A gate or diff report with its failing lines ("WORSE", "worse", "gate:
// FAILED") in red and its better ones ("better", "gate: passed") in green,
// when colour is on.
std::string coloured_verdicts(const std::string& text);

// A line for a person on stderr ("audit: ... on one thread"); nothing with --quiet.
void note(std::string_view text);

// Progress on one stderr line, redrawn at most ten times a second, only when
// stderr is a terminal and not --quiet: "audit: 1200/3000 cases (40.0%),
// 0:04 elapsed, ETA 0:06"; without a total, the count and the time.
class progress {
public:
    progress(std::string label, std::string unit, std::optional<double> total = std::nullopt);
    ~progress();
    progress(const progress&) = delete;
    progress& operator=(const progress&) = delete;
    bool shown() const { return shown_; }
    void set_total(double total) { total_ = total; }
    // `extra` is appended to the line (hunt: the best error so far).
    void update(double done, std::string_view extra = {});
    // The last state, then a newline (also on destruction).
    void finish();

private:
    void draw(double done, std::string_view extra);
    std::string label_, unit_;
    std::optional<double> total_;
    bool shown_ = false, drawn_ = false, finished_ = false;
    double last_done_ = 0;
    std::string last_extra_;
    std::chrono::steady_clock::time_point began_, last_draw_;
};

// "0:07", "12:03", "1:02:03".
std::string clock_text(double seconds);

}  // namespace rayverify::cli::terminal

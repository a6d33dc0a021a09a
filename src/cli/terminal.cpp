#include "cli/terminal.h"

#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rayverify::cli::terminal {
namespace {

struct state {
    bool quiet = false;
    bool colour = false;
    bool progress = false;
};

state& current() {
    static state s;
    return s;
}

bool colour_allowed() {
    const char* no_colour = std::getenv("NO_COLOR");
    if (no_colour != nullptr && no_colour[0] != '\0') return false;  // https://no-color.org
    const char* term = std::getenv("TERM");
    if (term != nullptr && std::strcmp(term, "dumb") == 0) return false;
    return isatty(STDOUT_FILENO) != 0;
}

// Notes and progress never fail a command: a stderr that cannot be written
// (closed by `2>&1 | head`) loses them, nothing else.
void to_stderr(std::string_view text) {
    std::fwrite(text.data(), 1, text.size(), stderr);
    std::fflush(stderr);
}

std::string painted(std::string_view text, const char* code) {
    if (!current().colour) return std::string(text);
    return fmt::format("\033[{}m{}\033[0m", code, text);
}

}  // namespace

void configure(bool quiet) {
    state& s = current();
    s.quiet = quiet;
    s.colour = colour_allowed();
    s.progress = !quiet && isatty(STDERR_FILENO) != 0;
}

bool quiet() { return current().quiet; }

std::size_t width() {
    std::size_t columns = 80;
    if (const char* env = std::getenv("COLUMNS"); env != nullptr && std::atoi(env) > 0) {
        columns = static_cast<std::size_t>(std::atoi(env));
    } else {
        winsize size{};
        if (isatty(STDOUT_FILENO) && ioctl(STDOUT_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0)
            columns = size.ws_col;
    }
    return std::clamp<std::size_t>(columns, 40, 200);
}

std::string worse(std::string_view text) { return painted(text, "1;31"); }
std::string better(std::string_view text) { return painted(text, "32"); }

std::string coloured_verdicts(const std::string& text) {
    if (!current().colour) return text;
    std::string out;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        const std::string_view line(text.data() + at, end - at);
        if (line.starts_with("WORSE") || line.starts_with("worse") || line.starts_with("gate: FAILED"))
            out += worse(line);
        else if (line.starts_with("better") || line.starts_with("gate: passed"))
            out += better(line);
        else
            out += line;
        if (end < text.size()) out += '\n';
        at = end + 1;
    }
    return out;
}

void note(std::string_view text) {
    if (!current().quiet) to_stderr(fmt::format("{}\n", text));
}

std::string clock_text(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
    return fmt::format("{}:{:02}", s / 60, s % 60);
}

progress::progress(std::string label, std::string unit, std::optional<double> total)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), shown_(current().progress),
      began_(std::chrono::steady_clock::now()), last_draw_(began_) {}

progress::~progress() { finish(); }

void progress::update(double done, std::string_view extra) {
    last_done_ = done;
    last_extra_ = std::string(extra);
    if (!shown_) return;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    draw(done, extra);
}

namespace {

// A count as an integer, a time to a tenth of a second.
std::string amount(double x) {
    if (x == std::floor(x) && x < 1e15) return fmt::format("{}", static_cast<unsigned long long>(x));
    return fmt::format("{:.1f}", x);
}

}  // namespace

void progress::draw(double done, std::string_view extra) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
    std::string line = fmt::format("{}: {}", label_, amount(done));
    if (total_ && *total_ > 0) {
        const double share = std::min(done / *total_, 1.0);
        line += fmt::format("/{} {} ({:.1f}%), {} elapsed", amount(*total_), unit_, 100.0 * share,
                            clock_text(elapsed));
        if (share > 0 && share < 1) line += ", ETA " + clock_text(elapsed * (1 - share) / share);
    } else {
        line += fmt::format(" {}, {} elapsed", unit_, clock_text(elapsed));
    }
    if (!extra.empty()) line += fmt::format(", {}", extra);
    to_stderr(fmt::format("\r\033[K{}", line));
    drawn_ = true;
}

void progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (!shown_ || !drawn_) return;
    draw(last_done_, last_extra_);
    to_stderr("\n");
}

}  // namespace rayverify::cli::terminal

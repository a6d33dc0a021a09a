#include "cli/app.h"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>
#include <thread>

#include "cli/terminal.h"
#include "core/build_info.h"
#include "core/spelling.h"
#include "core/target_name.h"
#include "report/audit_report.h"

namespace rayverify::cli {
namespace {

// `text` broken into lines of at most `width` columns (words are not split),
// each after the first indented by `indent`; existing newlines are kept.
std::string wrapped(const std::string& text, std::size_t width, std::size_t indent, std::size_t first_column) {
    std::string out;
    std::size_t column = first_column;
    std::istringstream paragraphs(text);
    std::string paragraph;
    bool first_paragraph = true;
    while (std::getline(paragraphs, paragraph)) {
        if (!first_paragraph) {
            out += "\n" + std::string(indent, ' ');
            column = indent;
        }
        first_paragraph = false;
        std::istringstream words(paragraph);
        std::string word;
        bool line_start = true;
        while (words >> word) {
            if (!line_start && column + 1 + word.size() > width) {
                out += "\n" + std::string(indent, ' ');
                column = indent;
                line_start = true;
            }
            if (!line_start) {
                out += ' ';
                ++column;
            }
            out += word;
            column += word.size();
            line_start = false;
        }
    }
    return out;
}

// CLI11's help, with every description wrapped to the terminal's width.
class wrapping_formatter : public CLI::Formatter {
public:
    std::string make_option(const CLI::Option* opt, bool is_positional) const override {
        return line(make_option_name(opt, is_positional) + make_option_opts(opt), make_option_desc(opt));
    }
    std::string make_subcommand(const CLI::App* sub) const override {
        return line(sub->get_display_name(true), sub->get_description());
    }
    std::string make_description(const CLI::App* app) const override {
        const std::string text = CLI::Formatter::make_description(app);
        return text.empty() ? text : wrapped(text, terminal::width(), 0, 0) + "\n";
    }

private:
    // "  NAME" in the left column, the description beside it (or below, when the name is wider).
    std::string line(const std::string& name, const std::string& description) const {
        std::string out = "  " + name;
        if (out.size() > terminal::width()) out = "  " + wrapped(name, terminal::width(), 6, 2);
        if (description.empty()) return out + "\n";
        const std::size_t column = std::max<std::size_t>(column_width_, 8);
        const std::size_t newline = out.rfind('\n');
        const std::size_t last = newline == std::string::npos ? out.size() : out.size() - newline - 1;
        if (last >= column) {
            out += "\n" + std::string(column, ' ');
        } else {
            out += std::string(column - last, ' ');
        }
        return out + wrapped(description, std::max(terminal::width(), column + 20), column, column) + "\n";
    }
};

std::vector<std::string> subcommand_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        names.push_back(sub->get_name());
    return names;
}

std::vector<std::string> option_names(const CLI::App& app, bool hidden = false) {
    std::vector<std::string> names;
    for (const CLI::Option* opt : app.get_options()) {
        if (opt->get_group().empty() && !hidden) continue;  // deprecated spellings are not suggested
        for (const std::string& n : opt->get_lnames()) names.push_back("--" + n);
    }
    return names;
}

// The subcommand the arguments chose (the deepest named one), or the app;
// `next` is the index of the argument after its name.
const CLI::App* chosen(const CLI::App& app, const std::vector<std::string>& args, std::string& path,
                       std::size_t& next) {
    const CLI::App* at = &app;
    path = app.get_name();
    next = 0;
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i].starts_with("-")) continue;
        const auto subs = at->get_subcommands([&](const CLI::App* s) { return s->get_name() == args[i]; });
        if (subs.empty()) continue;
        at = subs.front();
        path += " " + args[i];
        next = i + 1;
    }
    return at;
}

}  // namespace

std::string version_text() { return fmt::format("rayverify {}\nbuild: {}", build_info::version, build_summary()); }

unsigned thread_count(unsigned requested) {
    return requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t best_distance = 3;
    for (const std::string& c : candidates) {
        const std::size_t d = edit_distance(word, c);
        if (d < best_distance || (best.empty() && word.size() >= 3 && c.starts_with(word))) {
            best = c;
            best_distance = std::min(d, best_distance);
        }
    }
    return best;
}

void configure_app(CLI::App& app, global_options& options) {
    app.formatter(std::make_shared<wrapping_formatter>());
    app.fallthrough();
    app.set_version_flag("--version", version_text());
    app.add_flag("-q,--quiet", options.quiet, "No progress and no notes on stderr (errors still); stdout unchanged");
    app.add_option("--generate-completion", options.completion, "Print the bash or zsh completion script")
        ->check(CLI::IsMember({"bash", "zsh"}))
        ->group("");
    app.add_flag("--generate-man", options.man, "Print the man page (groff)")->group("");
}

std::string parse_error_text(const CLI::App& app, const CLI::ParseError& error, const std::vector<std::string>& args) {
    std::string path;
    std::size_t next = 0;
    const CLI::App* at = chosen(app, args, path, next);
    std::string what = error.what();
    std::string hint;
    // The first word after the chosen command that names no subcommand, where one is expected.
    if (at == &app || !at->get_subcommands([](const CLI::App*) { return true; }).empty()) {
        for (std::size_t i = next; i < args.size(); ++i) {
            const std::string& arg = args[i];
            if (arg.starts_with("-")) continue;
            if (std::string sub; (sub = closest(arg, subcommand_names(*at))).size() && sub != arg) {
                what = fmt::format("'{}' is not a {} command", arg, path);
                hint = fmt::format("did you mean '{} {}'?", path, sub);
            }
            break;
        }
    }
    // The first option the chosen command does not know.
    if (hint.empty()) {
        std::vector<std::string> known = option_names(*at);
        if (at != &app)
            for (const std::string& n : option_names(app)) known.push_back(n);
        std::vector<std::string> accepted = option_names(*at, true);
        if (at != &app)
            for (const std::string& n : option_names(app, true)) accepted.push_back(n);
        for (const std::string& arg : args) {
            const std::string name = arg.substr(0, arg.find('='));
            if (!name.starts_with("--") || std::find(accepted.begin(), accepted.end(), name) != accepted.end())
                continue;
            if (const std::string near = closest(name, known); !near.empty()) {
                hint = fmt::format("did you mean '{}' for '{}'?", near, name);
                break;
            }
        }
    }
    // What the user typed is echoed in `what` and `hint`: shown escaped, so
    // that no escape sequence or newline of theirs reaches the terminal raw.
    std::string text = fmt::format("rayverify: error: {}\n", escaped_control(what));
    if (!hint.empty()) text += fmt::format("rayverify: {}\n", escaped_control(hint));
    text += fmt::format("run '{} --help' for the options\n", path);
    return text;
}

void note_deprecated(const std::string& command, const std::string& old_names, const std::string& replacement) {
    terminal::note(fmt::format("rayverify {}: {} is deprecated, use {}", command, old_names, replacement));
}

}  // namespace rayverify::cli

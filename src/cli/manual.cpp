#include "cli/manual.h"

#include <fmt/format.h>

#include <algorithm>

#include "cli/commands.h"
#include "compare/hunt.h"
#include "core/build_info.h"
#include "corpus/generators.h"
#include "intersectors/registry.h"

namespace rayverify::cli {
namespace {

// What an option's value is, for completion: nothing (a flag), a file, a
// directory, one of a list of words, or something to type (a number, a spec).
struct value_kind {
    enum { none, file, directory, words, other } kind = none;
    std::vector<std::string> list;
};

std::vector<std::string> variant_names() {
    std::vector<std::string> names;
    for (const variant& v : builtin_variants()) names.push_back(v.name);
    return names;
}

std::vector<std::string> family_names() {
    std::vector<std::string> names;
    for (const family_info& f : generator_families()) names.emplace_back(f.name);
    return names;
}

bool takes_value(const CLI::Option* opt) { return opt->get_items_expected_max() > 0; }

std::string primary_name(const CLI::Option* opt) {
    if (!opt->get_lnames().empty()) return opt->get_lnames().front();
    if (!opt->get_snames().empty()) return opt->get_snames().front();
    return opt->get_name();
}

value_kind value_of(const CLI::Option* opt, const std::string& command) {
    if (!takes_value(opt)) return {};
    const std::string name = primary_name(opt);
    if (name == "variant") return {value_kind::words, variant_names()};
    if (name == "precision") return {value_kind::words, precision_names()};
    if (name == "family") return {value_kind::words, family_names()};
    if (name == "objective") return {value_kind::words, hunt_objective_names()};
    if (name == "strategy") return {value_kind::words, hunt_strategy_names()};
    if (name == "oracle-route") return {value_kind::words, oracle_route_names()};
    static const std::vector<std::string> typed = {
        "threads", "seed",  "count",  "repetitions", "min-time", "sweep",   "evaluations", "finds",
        "examples", "seconds", "budget", "plugin-timeout", "shard", "tolerance", "generate", "case"};
    if (std::find(typed.begin(), typed.end(), name) != typed.end()) return {value_kind::other, {}};
    if (name == "report" || name == "corpus-dir" || name == "shards" || (name == "output" && command == "render"))
        return {value_kind::directory, {}};
    return {value_kind::file, {}};
}

// The subcommands of `app` (in the order they were added), and of each.
std::vector<const CLI::App*> subcommands(const CLI::App& app) {
    return app.get_subcommands([](const CLI::App*) { return true; });
}

// Visible options (hidden ones have an empty group), help excluded.
std::vector<const CLI::Option*> visible_options(const CLI::App& app) {
    return app.get_options([](const CLI::Option* o) { return !o->get_group().empty(); });
}

std::vector<std::string> flag_spellings(const CLI::Option* opt) {
    std::vector<std::string> out;
    for (const std::string& s : opt->get_snames()) out.push_back("-" + s);
    for (const std::string& l : opt->get_lnames()) out.push_back("--" + l);
    return out;
}

std::string first_sentence(std::string text) {
    for (std::size_t i = 0; i + 1 < text.size(); ++i)
        if (text[i] == '.' && text[i + 1] == ' ') return text.substr(0, i);
    if (const std::size_t nl = text.find('\n'); nl != std::string::npos) text = text.substr(0, nl);
    return text;
}

std::string joined(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
    return out;
}

// --- bash ---------------------------------------------------------------

// The case arms of one command: its options, and what each option's value completes to.
std::string bash_command(const CLI::App& command, const std::string& key) {
    std::vector<std::string> words, files, directories;
    std::vector<std::pair<std::string, std::string>> lists;  // option → its words
    for (const CLI::Option* opt : visible_options(command)) {
        if (opt->get_positional() && !opt->nonpositional()) continue;
        const std::vector<std::string> spellings = flag_spellings(opt);
        words.insert(words.end(), spellings.begin(), spellings.end());
        const value_kind v = value_of(opt, command.get_name());
        for (const std::string& s : spellings) {
            if (v.kind == value_kind::file) files.push_back(s);
            if (v.kind == value_kind::directory) directories.push_back(s);
            if (v.kind == value_kind::words) lists.emplace_back(s, joined(v.list));
        }
    }
    for (const CLI::App* sub : subcommands(command)) words.push_back(sub->get_name());
    std::string out = fmt::format("        {})\n            case \"$prev\" in\n", key);
    if (!files.empty()) {
        std::string pattern;
        for (const std::string& f : files) pattern += (pattern.empty() ? "" : "|") + f;
        out += fmt::format("                {}) COMPREPLY=($(compgen -f -- \"$cur\")); return ;;\n", pattern);
    }
    if (!directories.empty()) {
        std::string pattern;
        for (const std::string& d : directories) pattern += (pattern.empty() ? "" : "|") + d;
        out += fmt::format("                {}) COMPREPLY=($(compgen -d -- \"$cur\")); return ;;\n", pattern);
    }
    for (const auto& [option, list] : lists)
        out += fmt::format("                {}) COMPREPLY=($(compgen -W \"{}\" -- \"$cur\")); return ;;\n", option, list);
    out += "            esac\n";
    out += fmt::format("            words=\"{}\" ;;\n", joined(words));
    return out;
}

// --- zsh ----------------------------------------------------------------

std::string zsh_escaped(std::string text) {
    std::string out;
    for (char c : text) {
        if (c == '\'') out += "'\\''";
        else if (c == '[' || c == ']' || c == ':' || c == '\\') out += std::string("\\") + c;
        else if (c == '\n') out += ' ';
        else out += c;
    }
    return out;
}

std::string zsh_arguments(const CLI::App& command) {
    std::string out;
    for (const CLI::Option* opt : visible_options(command)) {
        if (opt->get_positional() && !opt->nonpositional()) continue;
        const value_kind v = value_of(opt, command.get_name());
        std::string action;
        if (v.kind == value_kind::file) action = ":file:_files";
        if (v.kind == value_kind::directory) action = ":directory:_files -/";
        if (v.kind == value_kind::words) action = ":value:(" + joined(v.list) + ")";
        if (v.kind == value_kind::other) action = ":value: ";
        const std::string repeat = opt->get_items_expected_max() > 1 ? "*" : "";
        const std::string description = zsh_escaped(first_sentence(opt->get_description()));
        for (const std::string& s : flag_spellings(opt))
            out += fmt::format(" \\\n        '{}{}[{}]{}'", repeat, s, description, action);
    }
    return out;
}

// --- man ----------------------------------------------------------------

// Text for roff: backslashes and hyphens escaped, a line never starting with
// a control character, and every non-ASCII character as its \[uXXXX] escape.
std::string roff(const std::string& text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x80) {
            const int length = byte >= 0xf0 ? 4 : byte >= 0xe0 ? 3 : 2;
            unsigned code = byte & (length == 4 ? 0x07u : length == 3 ? 0x0fu : 0x1fu);
            for (int k = 1; k < length && i + 1 < text.size(); ++k)
                code = (code << 6) | (static_cast<unsigned char>(text[++i]) & 0x3fu);
            out += fmt::format("\\[u{:04X}]", code);
            continue;
        }
        if (c == '\\') out += "\\e";
        else if (c == '-') out += "\\-";
        else if (c == '\n') out += "\n.br\n";
        else out += c;
        if ((c == '\n') && i + 1 < text.size() && (text[i + 1] == '.' || text[i + 1] == '\'')) out += "\\&";
    }
    if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out = "\\&" + out;
    return out;
}

// The word a value is shown as: PATH, DIR, the choices, or CLI11's type name.
std::string value_name(const CLI::Option* opt, const std::string& command) {
    const value_kind v = value_of(opt, command);
    if (v.kind == value_kind::file) return "PATH";
    if (v.kind == value_kind::directory) return "DIR";
    if (v.kind == value_kind::words && v.list.size() <= 4) {
        std::string choices;
        for (const std::string& w : v.list) choices += (choices.empty() ? "" : "|") + w;
        return choices;
    }
    if (v.kind == value_kind::words) return "NAME";
    return roff(opt->get_type_name().empty() ? "VALUE" : opt->get_type_name().substr(0, opt->get_type_name().find(':')));
}

std::string man_options(const CLI::App& command) {
    std::string out;
    for (const CLI::Option* opt : visible_options(command)) {
        std::string names;
        if (opt->get_positional() && !opt->nonpositional()) {
            names = "\\fI" + roff(opt->get_name()) + "\\fR";
        } else {
            for (const std::string& s : flag_spellings(opt)) names += (names.empty() ? "" : ", ") + ("\\fB" + roff(s) + "\\fR");
            if (takes_value(opt)) names += " \\fI" + value_name(opt, command.get_name()) + "\\fR";
        }
        out += fmt::format(".TP\n{}\n{}\n", names, roff(opt->get_description()));
    }
    return out;
}

void man_command(std::string& out, const CLI::App& command, const std::string& path) {
    out += fmt::format(".SS \"{}\"\n{}\n", roff(path), roff(command.get_description()));
    out += man_options(command);
    for (const CLI::App* sub : subcommands(command)) man_command(out, *sub, path + " " + sub->get_name());
}

}  // namespace

std::string bash_completion(const CLI::App& app) {
    std::vector<std::string> top;
    for (const CLI::App* sub : subcommands(app)) top.push_back(sub->get_name());
    for (const CLI::Option* opt : visible_options(app))
        for (const std::string& s : flag_spellings(opt)) top.push_back(s);
    std::string out = "# bash completion for rayverify, generated from its command-line definition\n"
                      "# (rayverify --generate-completion bash). Installed as\n"
                      "# share/bash-completion/completions/rayverify.\n"
                      "_rayverify() {\n"
                      "    local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"${COMP_WORDS[COMP_CWORD-1]}\"\n"
                      "    local command=\"\" words=\"\" i\n"
                      "    # The subcommand path so far, e.g. \"corpus generate\".\n"
                      "    for ((i = 1; i < COMP_CWORD; i++)); do\n"
                      "        case \"${COMP_WORDS[i]}\" in\n"
                      "            -*) ;;\n";
    std::string names;
    for (const CLI::App* sub : subcommands(app)) {
        names += (names.empty() ? "" : "|") + sub->get_name();
        for (const CLI::App* subsub : subcommands(*sub)) names += "|" + subsub->get_name();
    }
    out += fmt::format("            {}) command=\"${{command:+$command }}${{COMP_WORDS[i]}}\" ;;\n", names);
    out += "        esac\n    done\n    case \"$command\" in\n";
    out += fmt::format("        \"\") words=\"{}\" ;;\n", joined(top));
    for (const CLI::App* sub : subcommands(app)) {
        out += bash_command(*sub, "\"" + sub->get_name() + "\"");
        for (const CLI::App* subsub : subcommands(*sub))
            out += bash_command(*subsub, "\"" + sub->get_name() + " " + subsub->get_name() + "\"");
    }
    out += "    esac\n    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n}\ncomplete -F _rayverify rayverify\n";
    return out;
}

std::string zsh_completion(const CLI::App& app) {
    std::string out = "#compdef rayverify\n"
                      "# zsh completion for rayverify, generated from its command-line definition\n"
                      "# (rayverify --generate-completion zsh). Installed as share/zsh/vendor-completions/_rayverify.\n\n"
                      "_rayverify() {\n"
                      "    local -a commands\n"
                      "    commands=(\n";
    for (const CLI::App* sub : subcommands(app))
        out += fmt::format("        '{}:{}'\n", sub->get_name(), zsh_escaped(first_sentence(sub->get_description())));
    out += "    )\n"
           "    local curcontext=\"$curcontext\" state line\n"
           "    _arguments -C" + zsh_arguments(app) + " \\\n"
           "        '1:command:->command' \\\n"
           "        '*::argument:->argument'\n"
           "    case $state in\n"
           "        command) _describe 'rayverify command' commands ;;\n"
           "        argument)\n"
           "            case $words[1] in\n";
    for (const CLI::App* sub : subcommands(app)) {
        const auto subs = subcommands(*sub);
        if (subs.empty()) {
            out += fmt::format("                {}) _arguments{} '*:file:_files' ;;\n", sub->get_name(),
                               zsh_arguments(*sub));
            continue;
        }
        out += fmt::format("                {})\n                    if (( CURRENT == 2 )); then\n"
                           "                        _values '{} command'",
                           sub->get_name(), sub->get_name());
        for (const CLI::App* s : subs)
            out += fmt::format(" '{}[{}]'", s->get_name(), zsh_escaped(first_sentence(s->get_description())));
        out += "\n                    else\n                        case $words[2] in\n";
        for (const CLI::App* s : subs)
            out += fmt::format("                            {}) _arguments{} ;;\n", s->get_name(),
                               zsh_arguments(*s));
        out += "                        esac\n                    fi ;;\n";
    }
    out += "            esac ;;\n    esac\n}\n\n_rayverify \"$@\"\n";
    return out;
}

std::string man_page(const CLI::App& app) {
    std::string out = fmt::format(".\\\" The rayverify man page, generated from its command-line definition (rayverify "
                                  "--generate-man).\n.TH RAYVERIFY 1 \"\" \"rayverify {}\" \"User Commands\"\n",
                                  build_info::version);
    out += ".SH NAME\nrayverify \\- audit floating\\-point ray\\(ensphere intersection code against an exact "
           "oracle\n";
    out += ".SH SYNOPSIS\n.B rayverify\n[\\fB\\-\\-quiet\\fR] \\fICOMMAND\\fR [\\fIOPTIONS\\fR]\n.br\n"
           ".B rayverify\n\\fB\\-\\-help\\fR | \\fB\\-\\-version\\fR\n";
    out += ".SH DESCRIPTION\n" + roff(app.get_description()) + "\n";
    out += ".PP\nOptions of rayverify itself may be given before or after the command.\n" + man_options(app);
    out += ".SH COMMANDS\n";
    for (const CLI::App* sub : subcommands(app)) man_command(out, *sub, "rayverify " + sub->get_name());
    out += ".SH OUTPUTS\n"
           "A command prints its table on stdout, and progress (on a terminal) and notes on stderr; "
           "\\fB\\-\\-quiet\\fR silences stderr but for errors. Files: \\fB\\-\\-report\\fR \\fIDIR\\fR is a "
           "directory of reports (report.json, summary.txt, report.md, plots); \\fB\\-o\\fR, "
           "\\fB\\-\\-output\\fR names a command's one product (a corpus file, a directory of images); other "
           "files are named by their format (\\fB\\-\\-per\\-case\\fR, \\fB\\-\\-junit\\fR, "
           "\\fB\\-\\-summary\\-md\\fR, \\fB\\-\\-benchmark\\-json\\fR). Every output file appears whole or not "
           "at all.\n";
    out += ".SH EXIT STATUS\n.TP\n0\nno finding\n.TP\n1\nfindings: a variant disagrees with the exact answer, "
           "a figure is worse than its baseline, or a corpus differs from its manifest\n.TP\n2\nusage or input "
           "error (the message names file, line and field); nothing is written\n.TP\n3\ninternal error\n";
    out += ".SH ENVIRONMENT\n.TP\n.B NO_COLOR\nWhen set and not empty, no colour on a terminal.\n.TP\n.B COLUMNS\n"
           "The width help is wrapped to (default: the terminal's).\n";
    out += ".SH FILES\n.TP\n.I share/rayverify/corpus\nThe shipped corpus, read when no \\fB\\-\\-corpus\\fR is "
           "given.\n.TP\n.I share/rayverify/plot_report.py\nDraws the report plots (python3\\-matplotlib).\n";
    out += ".SH SEE ALSO\nThe documentation in share/doc/rayverify, and docs/ in the source.\n";
    return out;
}

}  // namespace rayverify::cli

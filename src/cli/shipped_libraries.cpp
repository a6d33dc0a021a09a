#include "cli/shipped_libraries.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/contract.h"
#include "core/input_error.h"
#include "core/installed_data.h"
#include "corpus/json_input.h"
#include "plugin/plugin_loader.h"

namespace rayverify::cli {
namespace {

namespace fs = std::filesystem;

std::string file_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error(path.string(), 0, "", "cannot open for reading");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A JSON manifest: an array of objects whose listed members are strings (or
// null), and whose optional members, where present, are too.
nlohmann::ordered_json manifest(const fs::path& path, const std::vector<std::string>& members,
                                const std::vector<std::string>& optional_members = {}) {
    const nlohmann::ordered_json doc = parse_json_input(file_text(path), path.string());
    if (!doc.is_array()) throw input_error(path.string(), 1, "", "expected an array of libraries");
    const auto text_or_null = [](const nlohmann::ordered_json& v) { return v.is_string() || v.is_null(); };
    for (std::size_t i = 0; i < doc.size(); ++i) {
        for (const std::string& m : members)
            if (!doc[i].is_object() || !doc[i].contains(m) || !text_or_null(doc[i][m]))
                throw input_error(path.string(), 0, fmt::format("[{}].{}", i, m), "missing, or not a string");
        for (const std::string& m : optional_members)
            if (doc[i].contains(m) && !text_or_null(doc[i][m]))
                throw input_error(path.string(), 0, fmt::format("[{}].{}", i, m), "not a string");
    }
    return doc;
}

std::string text_member(const nlohmann::ordered_json& object, const char* member) {
    if (!object.contains(member)) return {};
    const auto& value = object.at(member);
    return value.is_string() ? value.get<std::string>() : std::string();
}

// What a command prints on its standard output, trimmed; empty when it fails.
// Only fixed commands built here from checked words are run.
std::string command_output(const std::string& command) {
    std::FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) return {};
    std::string out;
    std::array<char, 256> buffer{};
    while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr && out.size() < 4096) out += buffer.data();
    const int status = pclose(pipe);
    if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return {};
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
}

bool plain_word(const std::string& word) {
    return !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char ch) {
        return std::isalnum(ch) || ch == '-' || ch == '.' || ch == '+' || ch == '_' || ch == '/' || ch == '@';
    });
}

// The installed version of a Debian package, as dpkg says; empty when unknown.
std::string debian_package_version(const std::string& package) {
    if (!plain_word(package)) return {};
    return command_output("dpkg-query -W -f='${Version}' " + package + " 2>/dev/null");
}

std::string shell_quoted(const std::string& text) {
    std::string out = "'";
    for (char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

std::vector<precision> precisions_of(const variant& v) {
    std::vector<precision> out;
    for (precision p : {precision::binary32, precision::binary64})
        if (v.runs_in(p)) out.push_back(p);
    return out;
}

// The C and C++ libraries: the plugins the build made, and those it could not.
void add_native_libraries(std::vector<shipped_library>& out) {
    const fs::path listed =
        installed_file(RAYVERIFY_INSTALLED_NATIVE_ENGINES, "native_engines.json", RAYVERIFY_NATIVE_ENGINES);
    std::error_code error;
    if (!fs::exists(listed, error)) return;
    const nlohmann::ordered_json doc =
        manifest(listed, {"name", "library", "package", "plugin", "why_not"}, {"depends_on_cpu", "kernel_of"});
    for (const auto& entry : doc) {
        shipped_library lib;
        lib.name = text_member(entry, "name");
        lib.how = shipped_library::runner::plugin;
        lib.depends_on_cpu = text_member(entry, "depends_on_cpu");
        lib.kernel_of = text_member(entry, "kernel_of");
        const std::string package = text_member(entry, "package");
        lib.identity = {text_member(entry, "library"), "", "Debian package " + package, ""};
        lib.why_not = text_member(entry, "why_not");
        const std::string plugin = text_member(entry, "plugin");
        if (lib.why_not.empty() && plugin.empty()) lib.why_not = "no plugin was built for it";
        if (lib.why_not.empty()) {
            // A relative path is relative to the list (an installed copy).
            lib.plugin = fs::path(plugin).is_absolute() ? fs::path(plugin) : listed.parent_path() / plugin;
            try {
                const variant v = load_plugin(lib.plugin);
                lib.precisions = precisions_of(v);
                lib.contract = format_contract(v.promises);
                lib.api = v.citation;
                if (v.library) {
                    lib.identity.version = v.library->version;
                    lib.identity.configuration = v.library->configuration;
                }
            } catch (const plugin_cannot_run_here& e) {
                lib.why_not = e.reason();
                lib.runs_elsewhere_only = true;
            } catch (const input_error& e) {
                lib.why_not = fmt::format("its plugin cannot be loaded ({}); rebuild rayverify", e.what());
            }
        }
        if (lib.identity.version.empty()) lib.identity.version = debian_package_version(package);
        out.push_back(std::move(lib));
    }
}

// The environment the engines' node runs in, built by rayverify: the
// caller's PATH and HOME and nothing else, so that no NODE_OPTIONS (a
// --require that replaces Math.sqrt, a typo), NODE_PATH or other variable of
// the caller's reaches the library audited.
constexpr const char* node_environment = "env -i PATH=\"$PATH\" HOME=\"$HOME\" ";

// The node on PATH: its major version, or 0 with why not (not found, or its
// own answer to --version when it fails).
int node_major_version(std::string& why_not) {
    if (command_output("command -v node").empty()) {
        why_not = "node is not on PATH (Node.js 18 or later runs the JavaScript engines)";
        return 0;
    }
    const std::string version = command_output(std::string(node_environment) + "node --version 2>/dev/null");  // "v20.20.2"
    if (version.size() < 2 || version[0] != 'v') {
        const std::string said = command_output(std::string(node_environment) + "node --version 2>&1 || true");
        why_not = fmt::format("`node --version` fails: {}", said.empty() ? "(it printed nothing)" : said.substr(0, 200));
        return 0;
    }
    return std::atoi(version.c_str() + 1);
}

// The JavaScript libraries: each adapter's manifest entry and its package's install.
void add_javascript_libraries(std::vector<shipped_library>& out) {
    const fs::path dir = data_file("engines/js", RAYVERIFY_JS_ENGINES);
    std::error_code error;
    if (!fs::exists(dir / "engines.json", error)) return;
    const nlohmann::ordered_json doc =
        manifest(dir / "engines.json", {"name", "library", "package", "adapter", "precision", "contract", "api"});
    std::string node_why_not;
    const int node = node_major_version(node_why_not);
    const std::string install = fmt::format("run tools/setup.sh, or npm ci --prefix {}", dir.string());
    for (const auto& entry : doc) {
        shipped_library lib;
        lib.name = text_member(entry, "name");
        lib.how = shipped_library::runner::program;
        const std::string package = text_member(entry, "package");
        lib.identity = {text_member(entry, "library"), "", "npm package " + package, ""};
        lib.contract = text_member(entry, "contract");
        lib.api = text_member(entry, "api");
        const std::string prec = text_member(entry, "precision");
        if (const std::optional<precision> p = precision_from_name(prec))
            lib.precisions = {*p};
        else
            throw input_error((dir / "engines.json").string(), 0, lib.name + ".precision",
                              fmt::format("'{}' is not float or double", prec));
        const fs::path adapter = dir / text_member(entry, "adapter");
        lib.command = std::string(node_environment) + "node " + shell_quoted(adapter.string());
        const fs::path package_json = dir / "node_modules" / package / "package.json";
        if (fs::exists(package_json, error)) {
            try {
                const auto info = parse_json_input(file_text(package_json), package_json.string());
                if (info.contains("version") && info["version"].is_string())
                    lib.identity.version = info["version"].get<std::string>();
            } catch (const input_error&) {
                // left without a version: the install is damaged, which the next check says
            }
        }
        if (node == 0)
            lib.why_not = node_why_not;
        else if (node < 18)
            lib.why_not = fmt::format("node {} is too old (Node.js 18 or later runs the JavaScript engines)", node);
        else if (!fs::exists(adapter, error))
            lib.why_not = fmt::format("its adapter {} is missing", adapter.string());
        else if (lib.identity.version.empty())
            lib.why_not = fmt::format("npm package {} is not installed ({})", package, install);
        out.push_back(std::move(lib));
    }
}

}  // namespace

const std::vector<shipped_library>& shipped_libraries() {
    static const std::vector<shipped_library> all = [] {
        std::vector<shipped_library> out;
        add_native_libraries(out);
        add_javascript_libraries(out);
        return out;
    }();
    return all;
}

shipped_library available_library(const std::string& name) {
    const std::vector<shipped_library>& all = shipped_libraries();
    const auto found = std::find_if(all.begin(), all.end(), [&](const shipped_library& l) { return l.name == name; });
    if (found == all.end()) {
        std::string known;
        for (const shipped_library& l : all) known += (known.empty() ? "" : ", ") + l.name;
        throw input_error("", 0, "--engine",
                          fmt::format("unknown engine library '{}'; known: {} (`rayverify engines` lists them)", name,
                                      known.empty() ? "none (this build lists no engine library)" : known));
    }
    if (!found->available())
        throw input_error("", 0, "--engine",
                          fmt::format("engine library '{}' is not available{}: {}", name,
                                      found->runs_elsewhere_only ? " on this machine" : "", found->why_not));
    return *found;
}

std::vector<shipped_library> requested_libraries(const std::vector<std::string>& names) {
    std::vector<shipped_library> out;
    for (const std::string& name : names) {
        if (!name.ends_with(every_kernel_suffix)) {
            out.push_back(available_library(name));
            continue;
        }
        const std::string of = name.substr(0, name.size() - every_kernel_suffix.size());
        std::vector<std::string> pinned, runnable;
        for (const shipped_library& l : shipped_libraries()) {
            if (l.kernel_of != of) continue;
            pinned.push_back(l.name);
            if (l.available()) {
                out.push_back(l);
                runnable.push_back(l.name);
            }
        }
        if (pinned.empty())
            throw input_error("", 0, "--engine",
                              fmt::format("'{}': engine library '{}' has no pinned kernels (`rayverify engines` lists "
                                          "the libraries that do)",
                                          name, of));
        if (runnable.empty())
            throw input_error("", 0, "--engine",
                              fmt::format("'{}': none of {}'s pinned kernels ({}) is available on this machine", name,
                                          of, fmt::join(pinned, ", ")));
    }
    return out;
}

}  // namespace rayverify::cli

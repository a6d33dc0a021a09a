#include "plugin/plugin_builds.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "core/child_processes.h"
#include "core/hash.h"
#include "core/input_error.h"
#include "core/installed_data.h"
#include "core/process_status.h"

namespace rayverify {
// Named, not anonymous: the plugin layer is one unity translation unit.
namespace plugin_builds_detail {

namespace fs = std::filesystem;

// A command's merged standard output and error, and how it ended.
struct command_run {
    bool ran = false;      // started and ended by itself with status 0
    std::string output;    // what it printed (at most 1 MiB kept)
    std::string ending;    // "exited with status 1", "took longer than 300 s"
};

constexpr double compile_timeout_seconds = 300;

// Held from a compiler's fork until it is counted as started, and while a
// finished compiler's session is ended: end_program_session kills every
// child of rayverify not yet counted as started, and keeps its tables in
// static storage (compilers run two at a time).
std::mutex children_mutex;

// Runs `argv` (argv[0] looked up on PATH) with no input, its own session
// (killed with rayverify, and with everything it started on a timeout).
command_run run_command(const std::vector<std::string>& argv, double timeout_seconds) {
    command_run result;
    int out[2];
    if (::pipe2(out, O_CLOEXEC) != 0) {
        result.ending = fmt::format("cannot create a pipe: {}", std::strerror(errno));
        return result;
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const pid_t parent = ::getpid();
    std::unique_lock<std::mutex> starting(children_mutex);
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(out[0]);
        ::close(out[1]);
        result.ending = fmt::format("cannot start {}: {}", argv.front(), std::strerror(errno));
        return result;
    }
    if (pid == 0) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(127);
        ::setsid();
        const int null_input = ::open("/dev/null", O_RDONLY);
        if (null_input < 0 || ::dup2(null_input, STDIN_FILENO) < 0 || ::dup2(out[1], STDOUT_FILENO) < 0 ||
            ::dup2(out[1], STDERR_FILENO) < 0)
            ::_exit(127);
        ::close_range(3, ~0u, 0);
        ::execvp(args[0], args.data());
        const std::string why = fmt::format("cannot run {}: {}\n", argv.front(), std::strerror(errno));
        [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, why.data(), why.size());
        ::_exit(127);
    }
    ::close(out[1]);
    started_child(pid);
    program_session_opened(pid);
    starting.unlock();
    const auto deadline = deadline_after(timeout_seconds);
    bool timed_out = false;
    char buffer[4096];
    for (;;) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
        if (left <= 0) {
            timed_out = true;
            break;
        }
        pollfd p{out[0], POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) continue;
        const ssize_t n = ::read(out[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        if (result.output.size() < (std::size_t{1} << 20)) result.output.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(out[0]);
    if (timed_out) ::kill(-pid, SIGKILL);
    const std::optional<int> status = reap_child(pid, -pid, timed_out ? 0 : 10);
    {
        const std::lock_guard<std::mutex> ending(children_mutex);
        child_ended(pid);
        end_program_session(pid);
    }
    if (timed_out)
        result.ending = fmt::format("took longer than {:g} s and was stopped", timeout_seconds);
    else if (!status)
        result.ending = "could not be waited for";
    else if (WIFEXITED(*status) && WEXITSTATUS(*status) == 0)
        result.ran = true;
    else
        result.ending = describe_wait_status(*status);
    return result;
}

// The line of a compiler's output that says what went wrong: the first error,
// else the first line.
std::string first_error_line(const std::string& output, const std::string& ending) {
    std::istringstream lines(output);
    std::string first, line;
    while (std::getline(lines, line)) {
        if (first.empty() && !line.empty()) first = line;
        if (line.find("error:") != std::string::npos || line.find("undefined reference") != std::string::npos ||
            line.find("cannot run ") == 0) {
            first = line;
            break;
        }
    }
    if (first.size() > 400) first = first.substr(0, 400) + "...";
    if (first.empty()) return ending;
    return first;
}

bool is_cxx_source(const fs::path& p) { return language_of(p) == source_language::cxx; }

// A file's digest, "missing" for one that cannot be read: a dependency that
// is gone differs from any file's digest.
std::string file_digest(const fs::path& path) {
    fnv1a_digest digest;
    return add_file_bytes(digest, path) ? digest.text() : "missing";
}

// The files a make-style dependency file names (the compiler's -MD output):
// everything after the first "target:" and its continuations.
std::vector<std::string> dependencies_in(const fs::path& depfile) {
    std::ifstream in(depfile, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const std::string all = text.str();
    std::vector<std::string> files;
    const std::size_t colon = all.find(": ");
    if (colon == std::string::npos) return files;
    std::string word;
    for (std::size_t i = colon + 1; i < all.size(); ++i) {
        const char c = all[i];
        if (c == '\\' && i + 1 < all.size() && (all[i + 1] == '\n' || all[i + 1] == '\r')) {
            ++i;
            continue;
        }
        if (c == '\\' && i + 1 < all.size() && all[i + 1] == ' ') {
            word += ' ';
            ++i;
            continue;
        }
        if (c == ' ' || c == '\n' || c == '\t' || c == '\r') {
            if (!word.empty()) files.push_back(word);
            word.clear();
            if (c == '\n' && i + 1 < all.size() && all[i + 1] != ' ' && all[i + 1] != '\t') break;  // the next rule
            continue;
        }
        word += c;
    }
    if (!word.empty()) files.push_back(word);
    return files;
}

// The directory of the plugin API's header and of robust_sphere.h, installed
// beside the executable or in the source tree.
fs::path plugin_header_dir() {
    return installed_file("../include/rayverify/plugin", "rayverify_plugin.h", RAYVERIFY_PLUGIN_HEADER).parent_path();
}
fs::path robust_header_dir() {
    return installed_file("../include/rayverify", "robust_sphere.h", RAYVERIFY_ROBUST_HEADER).parent_path();
}

// The C source linked into a build whose component "FTZ/DAZ at load" is on:
// a constructor that sets them as crtfastmath.o does.
constexpr const char* ftz_daz_source = R"(/* rayverify builds: FTZ and DAZ set when the library loads, as crtfastmath.o does */
#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
__attribute__((constructor)) static void rayverify_ftz_daz_at_load(void) { _mm_setcsr(_mm_getcsr() | 0x8040); }
#elif defined(__aarch64__)
__attribute__((constructor)) static void rayverify_ftz_daz_at_load(void) {
    unsigned long fpcr;
    __asm__ volatile("mrs %0, fpcr" : "=r"(fpcr));
    fpcr |= 1ul << 24;
    __asm__ volatile("msr fpcr, %0" : : "r"(fpcr));
}
#endif
)";

std::string joined(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) {
        const bool plain = !w.empty() && w.find_first_of(" \t\"'\\$`") == std::string::npos;
        out += (out.empty() ? "" : " ") + (plain ? w : "'" + w + "'");
    }
    return out;
}

// The cache key of a build: everything that decides it except the headers,
// which the entry's dependency list checks. Paths are taken as given
// (relative to the working directory, where the compiler resolves them, and
// where an entry's dependencies are checked), rayverify's own headers by
// their content: the same source and headers build one entry wherever the
// tree lies.
std::string build_key(const build_spec& spec, const build_sources& sources) {
    std::string text = "rayverify-build 2\n";
    text += spec.compiler.name + '\n' + spec.compiler.c_command + '\n' + spec.compiler.cxx_command + '\n' +
            spec.compiler.version + '\n';
    for (const std::string& f : spec.flags) text += "flag " + f + '\n';
    text += spec.ftz_daz_at_load ? "ftz-daz\n" : "\n";
    for (const std::string& d : sources.include_dirs) text += "include " + d + '\n';
    for (const std::string& d : sources.defines) text += "define " + d + '\n';
    text += "std " + sources.c_standard + ' ' + sources.cxx_standard + '\n';
    for (const std::string& l : sources.libraries) text += "library " + l + '\n';
    for (const fs::path& s : sources.sources) text += "source " + s.string() + ' ' + file_digest(s) + '\n';
    for (const fs::path& s : sources.harness) text += "harness " + s.string() + ' ' + file_digest(s) + '\n';
    text += file_digest(plugin_header_dir() / "rayverify_plugin.h") + ' ' +
            file_digest(robust_header_dir() / "robust_sphere.h") + '\n';
    fnv1a_digest digest;
    digest.add(text);
    return digest.text();
}

std::vector<std::string> read_lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// The commands that build `spec` into `dir`: one compile per source (the
// harness and FTZ/DAZ object with the reference flags), then the link.
struct build_step {
    std::vector<std::string> argv;
    fs::path source, object, depfile;
};
struct build_plan {
    std::vector<build_step> compiles;
    build_step link;
};

build_plan plan_of(const build_spec& spec, const build_sources& sources, const fs::path& dir) {
    const std::vector<std::string> reference = flag_words(reference_flags_text);
    build_plan plan;
    bool any_cxx = false;
    const auto compile = [&](const fs::path& source, const std::vector<std::string>& flags) {
        build_step step;
        step.source = source;
        step.object = dir / fmt::format("{}-{}.o", plan.compiles.size(), source.stem().string());
        step.depfile = step.object.string() + ".d";
        any_cxx = any_cxx || is_cxx_source(source);
        step.argv = {is_cxx_source(source) ? spec.compiler.cxx_command : spec.compiler.c_command, "-c", "-fPIC"};
        const std::string& standard = is_cxx_source(source) ? sources.cxx_standard : sources.c_standard;
        if (!standard.empty()) step.argv.push_back("-std=" + standard);
        step.argv.insert(step.argv.end(), flags.begin(), flags.end());
        for (const std::string& d : sources.include_dirs) step.argv.push_back("-I" + d);
        for (const std::string& d : sources.defines) step.argv.push_back("-D" + d);
        step.argv.push_back("-I" + plugin_header_dir().string());
        step.argv.push_back("-I" + robust_header_dir().string());
        step.argv.insert(step.argv.end(), {"-MD", "-MF", step.depfile.string(), source.string(), "-o", step.object.string()});
        plan.compiles.push_back(step);
    };
    for (const fs::path& s : sources.sources) compile(s, spec.flags);
    for (const fs::path& s : sources.harness) compile(s, reference);
    if (spec.ftz_daz_at_load) compile(dir / "ftz_daz_at_load.c", reference);
    plan.link.argv = {any_cxx ? spec.compiler.cxx_command : spec.compiler.c_command, "-shared"};
    plan.link.argv.insert(plan.link.argv.end(), spec.flags.begin(), spec.flags.end());
    for (const build_step& c : plan.compiles) plan.link.argv.push_back(c.object.string());
    plan.link.argv.insert(plan.link.argv.end(), {"-o", (dir / "plugin.so").string()});
    for (const std::string& l : sources.libraries) plan.link.argv.push_back("-l" + l);
    plan.link.argv.push_back("-lm");
    return plan;
}

std::vector<std::string> command_lines_of(const build_plan& plan) {
    std::vector<std::string> lines;
    for (const build_step& c : plan.compiles) lines.push_back(joined(c.argv));
    lines.push_back(joined(plan.link.argv));
    return lines;
}

// The cached build in `entry`, when every file it was built from is unchanged
// (its dependencies as the compiler named them, read from here).
std::optional<built_plugin> cached_build(const build_spec& spec, const build_sources& sources, const fs::path& entry) {
    std::error_code error;
    if (!fs::is_regular_file(entry / "plugin.so", error)) return std::nullopt;
    const std::vector<std::string> deps = read_lines(entry / "dependencies.txt");
    if (deps.empty()) return std::nullopt;
    for (const std::string& line : deps) {
        const std::size_t space = line.find(' ');
        if (space == std::string::npos || file_digest(line.substr(space + 1)) != line.substr(0, space))
            return std::nullopt;
    }
    built_plugin b;
    b.spec = spec;
    b.command_lines = command_lines_of(plan_of(spec, sources, entry));
    b.plugin = entry / "plugin.so";
    b.cached = true;
    return b;
}

std::atomic<unsigned> partial_counter{0};

built_plugin build_one(const build_spec& spec, const build_sources& sources, const fs::path& cache_dir) {
    const fs::path entry = cache_dir / build_key(spec, sources);
    if (std::optional<built_plugin> hit = cached_build(spec, sources, entry)) return *hit;
    built_plugin b;
    b.spec = spec;
    b.command_lines = command_lines_of(plan_of(spec, sources, entry));  // as they read once the entry is in place
    const fs::path work =
        cache_dir / fmt::format("{}.partial-{}-{}", entry.filename().string(), ::getpid(), partial_counter++);
    std::error_code error;
    fs::remove_all(work, error);
    fs::create_directories(work, error);
    if (error) {
        b.failure = fmt::format("cannot create {}: {}", work.string(), error.message());
        return b;
    }
    if (spec.ftz_daz_at_load) std::ofstream(work / "ftz_daz_at_load.c") << ftz_daz_source;
    const build_plan plan = plan_of(spec, sources, work);
    bool ok = true;
    for (const build_step& step : plan.compiles) {
        const command_run run = run_command(step.argv, compile_timeout_seconds);
        if (!run.ran) {
            b.failure = fmt::format("{}: {}", step.source.filename().string(), first_error_line(run.output, run.ending));
            // gcc says "error: #error ...", clang quotes the directive's line under its message.
            b.refused_by_source = run.output.find("#error") != std::string::npos;
            ok = false;
            break;
        }
    }
    if (ok) {
        const command_run run = run_command(plan.link.argv, compile_timeout_seconds);
        if (!run.ran) {
            b.failure = fmt::format("link: {}", first_error_line(run.output, run.ending));
            ok = false;
        }
    }
    if (!ok) {
        fs::remove_all(work, error);
        return b;
    }
    {
        std::ofstream deps(work / "dependencies.txt");
        std::set<std::string> seen;
        for (const build_step& step : plan.compiles)
            for (const std::string& file : dependencies_in(step.depfile)) {
                if (fs::path(file).lexically_normal().string().find(work.string()) == 0 ||
                    fs::absolute(file).lexically_normal().string().find(fs::absolute(work).string()) == 0 ||
                    !seen.insert(file).second)
                    continue;
                deps << file_digest(file) << ' ' << file << '\n';
            }
    }
    for (const build_step& step : plan.compiles) {
        fs::remove(step.object, error);
        fs::remove(step.depfile, error);
    }
    fs::remove(work / "ftz_daz_at_load.c", error);
    fs::remove_all(entry, error);
    fs::rename(work, entry, error);
    if (error) {  // another run put the same entry in place first: use ours where it is
        b.plugin = work / "plugin.so";
        return b;
    }
    b.plugin = entry / "plugin.so";
    return b;
}

std::string first_line_of(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace plugin_builds_detail

using namespace plugin_builds_detail;

std::optional<source_language> language_of(const fs::path& source) {
    static const std::set<std::string> cxx = {".cc", ".cpp", ".cxx", ".c++", ".C"};
    const std::string extension = source.extension().string();
    if (extension == ".c") return source_language::c;
    if (cxx.contains(extension)) return source_language::cxx;
    return std::nullopt;
}

std::optional<compiler_driver> find_compiler(const std::string& name) {
    std::vector<std::pair<std::string, std::string>> candidates;
    if (name == "gcc")
        candidates = {{"gcc-12", "g++-12"}, {"gcc", "g++"}};
    else if (name == "clang")
        candidates = {{"clang-14", "clang++-14"}, {"clang", "clang++"}};
    else
        throw input_error("", 0, "--compiler", fmt::format("'{}' is not a compiler of the matrix: gcc or clang", name));
    for (const auto& [c, cxx] : candidates) {
        const command_run c_version = run_command({c, "--version"}, 30);
        const command_run cxx_version = run_command({cxx, "--version"}, 30);
        if (c_version.ran && cxx_version.ran) return compiler_driver{name, c, cxx, first_line_of(c_version.output)};
    }
    return std::nullopt;
}

std::vector<std::string> default_flag_sets() {
    return {"-O0", "-O2", "-O3", "-O2 -march=native", "-O2 -mfma -ffp-contract=fast", "-O2 -ffast-math", "-Ofast"};
}

std::vector<std::string> flag_words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

std::string build_name(const std::string& compiler, std::span<const std::string> flags) {
    std::string name = compiler;
    for (const std::string& f : flags) {
        std::string word = f.substr(f.find_first_not_of('-') == std::string::npos ? f.size() : f.find_first_not_of('-'));
        for (char& c : word)
            if (c == '/' || c == '#' || c == ' ' || static_cast<unsigned char>(c) < 0x20) c = '_';
        name += "-" + word;
    }
    return name;
}

void check_build_flags(std::span<const std::string> flags, const std::string& option) {
    // Flags that put code of their choosing into the build or run another
    // program in the compiler's place (the matrix would audit that code),
    // refused in every spelling that starts so (-includefoo.h, -fplugin=...).
    static const std::vector<std::string> injecting = {"-include", "-imacros", "-fplugin", "-specs", "--specs",
                                                        "-wrapper", "-B", "-fprofile-use", "-fauto-profile",
                                                        "--sysroot", "-isysroot", "-T", "--param=plugin"};
    // Flags that change what is built rather than how (the matrix compiles
    // and links each plugin itself): those alone, and those that take their
    // value attached (-ofile, -lm, -Wl,...).
    static const std::vector<std::string> structural_alone = {"-c", "-E", "-S", "-shared", "-static", "-pipe",
                                                               "-nostdlib", "-nostartfiles", "-save-temps", "-r"};
    static const std::vector<std::string> structural_prefix = {"-o", "-x", "-Wl,", "-Xlinker", "-Xassembler",
                                                                "-Xpreprocessor", "-M", "-l", "-L", "-Wa,", "-Wp,"};
    for (const std::string& f : flags) {
        if (f.starts_with("@"))
            throw input_error("", 0, option,
                              fmt::format("'{}' reads more flags from a file: give them here, each one seen", f));
        for (const std::string& r : injecting)
            if (f.starts_with(r))
                throw input_error("", 0, option,
                                  fmt::format("'{}' puts code of its choosing into the build (refused: the matrix "
                                              "would audit that code, not your source; docs/builds.md)",
                                              f));
        const bool structural =
            std::find(structural_alone.begin(), structural_alone.end(), f) != structural_alone.end() ||
            std::any_of(structural_prefix.begin(), structural_prefix.end(),
                        [&](const std::string& r) { return f.starts_with(r); });
        if (structural)
            throw input_error("", 0, option,
                              fmt::format("'{}' changes what is built, not how it is compiled (refused: builds "
                                          "compiles and links each plugin itself; -I and -D give include "
                                          "directories and defines, --std the language standard)",
                                          f));
        if (!f.starts_with("-"))
            throw input_error("", 0, option, fmt::format("'{}' is not a flag (a source goes before the options)", f));
    }
}

std::vector<built_plugin> build_plugins(std::span<const build_spec> specs, const build_sources& sources,
                                        const fs::path& cache_dir, unsigned jobs) {
    std::error_code error;
    fs::create_directories(cache_dir, error);
    if (error || !fs::is_directory(cache_dir, error))
        throw input_error(cache_dir.string(), 0, "--cache", "cannot create the build cache directory");
    std::vector<built_plugin> built(specs.size());
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
        for (std::size_t i; (i = next++) < specs.size();) built[i] = build_one(specs[i], sources, cache_dir);
    };
    std::vector<std::thread> threads;
    for (unsigned t = 1; t < std::max(1u, jobs) && t < specs.size(); ++t) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();
    return built;
}

fs::path default_build_cache() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/')
        return fs::path(xdg) / "rayverify" / "builds";
    if (const char* home = std::getenv("HOME"); home != nullptr && *home == '/')
        return fs::path(home) / ".cache" / "rayverify" / "builds";
    return fs::temp_directory_path() / fmt::format("rayverify-builds-{}", ::getuid());
}

std::vector<flag_component> flag_components(const build_spec& build, bool loads_with_ftz_daz) {
    std::vector<flag_component> out;
    const auto add = [&](const std::string& label, std::vector<std::string> flags) {
        if (std::none_of(out.begin(), out.end(), [&](const flag_component& c) { return c.label == label; }))
            out.push_back({label, std::move(flags), false});
    };
    const auto fast_math = [&] {
        for (const char* f : {"-fno-math-errno", "-ffinite-math-only", "-fno-signed-zeros", "-fno-trapping-math",
                              "-fassociative-math", "-freciprocal-math", "-ffp-contract=fast"})
            add(f, {f});
        if (build.compiler.name == "gcc") add("-fcx-limited-range", {"-fcx-limited-range"});
        // clang's -ffast-math also lets library functions be approximated (afn)
        // and, where crtfastmath.o is linked, compiles as if denormals were flushed.
        if (build.compiler.name == "clang") {
            add("-fapprox-func", {"-fapprox-func"});
            add("-fdenormal-fp-math=preserve-sign", {"-fdenormal-fp-math=preserve-sign,preserve-sign"});
        }
        add("__FAST_MATH__ defined", {"-D__FAST_MATH__"});
    };
    for (const std::string& f : build.flags) {
        if (f == "-ffast-math") {
            fast_math();
        } else if (f == "-Ofast") {
            add("-O3", {"-O3"});
            fast_math();
            if (build.compiler.name == "gcc") add("-fallow-store-data-races", {"-fallow-store-data-races"});
        } else {
            add(f, {f});
        }
    }
    if (loads_with_ftz_daz || build.ftz_daz_at_load) out.push_back({"FTZ/DAZ at load", {}, true});
    return out;
}

build_spec build_of_components(const build_spec& build, std::span<const flag_component> components) {
    build_spec out;
    out.compiler = build.compiler;
    for (const flag_component& c : components) {
        out.flags.insert(out.flags.end(), c.flags.begin(), c.flags.end());
        out.ftz_daz_at_load = out.ftz_daz_at_load || c.ftz_daz_at_load;
    }
    out.name = build_name(build.compiler.name, out.flags) + (out.ftz_daz_at_load ? "-ftz-daz-at-load" : "");
    return out;
}

std::vector<std::size_t> smallest_reproducing_subset(
    std::size_t n, const std::function<bool(const std::vector<std::size_t>&)>& reproduces) {
    std::map<std::vector<std::size_t>, bool> asked;
    const auto test = [&](std::vector<std::size_t> subset) {
        std::sort(subset.begin(), subset.end());
        const auto known = asked.find(subset);
        if (known != asked.end()) return known->second;
        const bool holds = reproduces(subset);
        asked.emplace(subset, holds);
        return holds;
    };
    if (test({})) return {};
    std::vector<std::size_t> current(n);
    for (std::size_t i = 0; i < n; ++i) current[i] = i;
    std::size_t granularity = 2;
    while (current.size() >= 2) {
        const std::size_t chunks = std::min(granularity, current.size());
        std::vector<std::vector<std::size_t>> parts(chunks);
        for (std::size_t i = 0; i < current.size(); ++i) parts[i * chunks / current.size()].push_back(current[i]);
        bool reduced = false;
        for (const auto& part : parts)
            if (test(part)) {
                current = part;
                granularity = 2;
                reduced = true;
                break;
            }
        if (!reduced)
            for (std::size_t p = 0; p < parts.size() && !reduced; ++p) {
                std::vector<std::size_t> complement;
                for (std::size_t q = 0; q < parts.size(); ++q)
                    if (q != p) complement.insert(complement.end(), parts[q].begin(), parts[q].end());
                std::sort(complement.begin(), complement.end());
                if (test(complement)) {
                    current = complement;
                    granularity = std::max<std::size_t>(granularity - 1, 2);
                    reduced = true;
                }
            }
        if (reduced) continue;
        if (chunks >= current.size()) break;
        granularity = std::min(granularity * 2, current.size());
    }
    return current;
}

}  // namespace rayverify

#include "plugin/plugin_loader.h"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <string_view>
#include <span>
#include <type_traits>
#include <vector>

#include "core/case_in_progress.h"
#include "core/exit_codes.h"
#include "core/outputs.h"
#include "plugin/plugin_host.h"
#include "plugin/plugin_library.h"

namespace rayverify {
namespace {

using namespace plugin_internal;

// ---- In process: a crash or an exit() names the plugin and the case ----
//
// A plugin that crashes, calls exit() or writes outside its roots is bad
// input, as isolated (exit 2, docs/outputs.md): the signal handler and the
// exit hook write what happened, remove the run's unfinished outputs
// (core/outputs.h) and end the process with status 2.

constexpr int crash_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
struct sigaction previous_actions[std::size(crash_signals)];
pid_t hooks_owner = 0;  // the process the hooks were installed in (not a forked child)

struct in_process_plugin {
    opened_library library;
    std::string name;  // read by the hooks
    std::string path;
};

// The plugin being called on this thread, nullptr between calls.
thread_local std::atomic<const in_process_plugin*> plugin_in_call{nullptr};
// The library being opened (dlopen, its constructors, describe()), empty otherwise.
std::atomic<const std::string*> library_loading{nullptr};
// The function being called: "double" or "float".
thread_local std::atomic<const char*> function_in_call{nullptr};

void write_text(std::string_view text) {
    while (!text.empty()) {
        const ssize_t n = ::write(STDERR_FILENO, text.data(), text.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        text.remove_prefix(static_cast<std::size_t>(n));
    }
}

std::string_view signal_name(int signal) {
    switch (signal) {
        case SIGSEGV: return "SIGSEGV";
        case SIGBUS: return "SIGBUS";
        case SIGFPE: return "SIGFPE";
        case SIGILL: return "SIGILL";
        default: return "SIGABRT";
    }
}

// "rayverify: error: LIB: field '--plugin': plugin 'NAME' WHAT on case ID (SOURCE), in its F function; ..."
// or, while loading, "rayverify: error: LIB: field '--plugin': WHAT while loading it (...)", as
// input_error and the isolated plugin word it. Only write(2) of text that exists already.
// Returns false when no plugin is being loaded or called on this thread.
bool tell_what_happened(std::initializer_list<std::string_view> what) {
    const in_process_plugin* plugin = plugin_in_call.load(std::memory_order_relaxed);
    const std::string* loading = library_loading.load(std::memory_order_relaxed);
    if (!plugin && !loading) return false;
    write_text("rayverify: error: ");
    write_text(plugin ? plugin->path : *loading);
    write_text(": field '--plugin': ");
    if (!plugin) {
        for (std::string_view part : what) write_text(part);
        write_text(" while loading it (dlopen, its constructors, or rayverify_plugin_describe())");
    } else {
        write_text("plugin '");
        write_text(plugin->name);
        write_text("' ");
        for (std::string_view part : what) write_text(part);
        if (const corpus_case* c = case_in_progress::current()) {
            write_text(" on case ");
            write_text(c->id);
            write_text(" (");
            write_text(c->source);
            write_text(")");
        } else {
            write_text(" on inputs given outside any audited case");
        }
        if (const char* function = function_in_call.load(std::memory_order_relaxed)) {
            write_text(", in its ");
            write_text(function);
            write_text(" function");
        }
    }
    write_text("; rerun with --isolate to have its process stopped instead of rayverify's; no output was written\n");
    return true;
}

// Only async-signal-safe calls: write(2), unlink(2) and rmdir(2) of paths that exist already, sigaction, _exit.
void crash_handler(int signal, siginfo_t*, void*) {
    const int saved_errno = errno;
    remove_unfinished_outputs();
    if (::getpid() == hooks_owner && tell_what_happened({"crashed (", signal_name(signal), ")"})) ::_exit(exit_input_error);
    // A crash of rayverify's own: back to what was there before (the default,
    // or a sanitizer's handler), which takes the signal as soon as this handler returns.
    for (std::size_t i = 0; i < std::size(crash_signals); ++i)
        if (crash_signals[i] == signal) ::sigaction(signal, &previous_actions[i], nullptr);
    ::raise(signal);
    errno = saved_errno;
}

// exit() from a plugin (a call, describe(), a constructor), or from anywhere
// while a command runs: never the command's own way out (main returns).
void exit_hook() {
    if (::getpid() != hooks_owner) return;  // an isolated plugin's child: its exit is reported by the parent
    if (!tell_what_happened({"called exit()"})) {
        if (!command_running()) return;
        write_text("rayverify: error: exit() was called while the command was running, not by rayverify (a plugin "
                   "loaded in this process?); rerun with --isolate; no output was written\n");
    }
    remove_unfinished_outputs();
    ::_exit(exit_input_error);
}

void install_hooks() {
    static std::once_flag once;
    std::call_once(once, [] {
        hooks_owner = ::getpid();
        // A stack of its own, so that a plugin that overflows its stack is reported too.
        stack_t current{};
        if (::sigaltstack(nullptr, &current) == 0 && (current.ss_flags & SS_DISABLE)) {
            static char alternate[1 << 16];
            stack_t ours{};
            ours.ss_sp = alternate;
            ours.ss_size = sizeof alternate;
            ::sigaltstack(&ours, nullptr);
        }
        struct sigaction action {};
        action.sa_sigaction = crash_handler;
        action.sa_flags = SA_SIGINFO | SA_ONSTACK;
        sigemptyset(&action.sa_mask);
        for (std::size_t i = 0; i < std::size(crash_signals); ++i)
            ::sigaction(crash_signals[i], &action, &previous_actions[i]);
        std::atexit(exit_hook);
    });
}

// Marks the call for the hooks.
class in_call {
public:
    in_call(const in_process_plugin& plugin, const char* function)
        : previous_(plugin_in_call.load(std::memory_order_relaxed)),
          previous_function_(function_in_call.load(std::memory_order_relaxed)) {
        plugin_in_call.store(&plugin, std::memory_order_relaxed);
        function_in_call.store(function, std::memory_order_relaxed);
        std::atomic_signal_fence(std::memory_order_seq_cst);
    }
    ~in_call() {
        std::atomic_signal_fence(std::memory_order_seq_cst);
        plugin_in_call.store(previous_, std::memory_order_relaxed);
        function_in_call.store(previous_function_, std::memory_order_relaxed);
    }
    in_call(const in_call&) = delete;
    in_call& operator=(const in_call&) = delete;

private:
    const in_process_plugin* previous_;
    const char* previous_function_;
};

template <class T, class Fn>
root_pair<T> call_in_process(const in_process_plugin& plugin, Fn intersect, const ray_sphere<T>& s, T tmin, T tmax,
                             bool interval_asked) {
    const T o[3] = {s.origin.x, s.origin.y, s.origin.z};
    const T d[3] = {s.direction.x, s.direction.y, s.direction.z};
    const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
    constexpr const char* function = std::is_same_v<T, float> ? "float" : "double";
    guarded_roots<T> buffer;
    int count = 0;
    {
        const in_call marked(plugin, function);
        count = intersect(o, d, c, s.radius, tmin, tmax, buffer.roots());
    }
    if (!buffer.intact())
        throw plugin_failure(plugin.path,
                             fmt::format("plugin '{}' wrote outside its roots[2] buffer {}, in its {} function",
                                         plugin.name, failing_case_text(), function),
                             failing_case(s, tmin, tmax, interval_asked));
    return root_pair<T>{count, buffer.roots()[0], buffer.roots()[1]};
}

// Wires a plugin's entry points into `v`: `call(s, tmin, tmax, interval_asked)`
// for ray_sphere<double> and, when the plugin has a float function,
// ray_sphere<float>. The plain functions pass the interval the contract is
// judged on; the interval kinds also get the ray's own interval.
template <class Call>
void bind_entry_points(variant& v, bool has_float, const Call& call) {
    const double tmin_d = interval_start<double>(v.promises);
    const float tmin_f = interval_start<float>(v.promises);
    constexpr double inf_d = std::numeric_limits<double>::infinity();
    constexpr float inf_f = std::numeric_limits<float>::infinity();
    v.run_double = [call, tmin_d](const ray_sphere<double>& s) { return call(s, tmin_d, inf_d, false); };
    if (has_float)
        v.run_float = [call, tmin_f](const ray_sphere<float>& s) { return call(s, tmin_f, inf_f, false); };
    if (!takes_interval(v.promises)) return;
    v.run_double_in = [call](const ray_sphere<double>& s, double tmin, double tmax) {
        return call(s, tmin, tmax, true);
    };
    if (has_float)
        v.run_float_in = [call](const ray_sphere<float>& s, float tmin, float tmax) {
            return call(s, tmin, tmax, true);
        };
}

// ---- Version 2: batch entry points --------------------------------------------

template <class T>
using rayverify_case_t = std::conditional_t<std::is_same_v<T, float>, rayverify_case_float, rayverify_case_double>;
template <class T>
using rayverify_answer_t = std::conditional_t<std::is_same_v<T, float>, rayverify_answer_float, rayverify_answer_double>;

// A version 2 plugin's cases in the ABI's structs (rays or segments), and its answers as rayverify holds them.
template <class Case, class T>
std::vector<Case> plugin_cases(std::span<const batch_case<T>> cases) {
    std::vector<Case> out;
    out.reserve(cases.size());
    for (const batch_case<T>& c : cases) out.push_back(plugin_case<Case>(c));
    return out;
}

// The struct a batch function of type Fn takes (rayverify_case_* or rayverify_segment_*).
template <class Fn>
struct batch_function_case;
template <class Case, class Answer>
struct batch_function_case<void (*)(const Case*, Answer*, std::size_t)> {
    using type = Case;
};

template <class T>
void take_answers(std::span<const rayverify_answer_t<T>> given, const contract& promises,
                  std::span<const batch_case<T>> cases, std::span<answer<T>> out) {
    for (std::size_t i = 0; i < cases.size(); ++i) out[i] = answer_from<T>(given[i], promises, cases[i].input);
}

// Wires a version 2 plugin's batch call into `v`: `batch(cases, answers)`
// for batch_case<float> and <double> (each only when the plugin runs in that
// precision), and from it the single-case functions (a batch of one).
template <class Batch>
void bind_batch_entry_points(variant& v, bool has_float, bool has_double, const Batch& batch) {
    const auto bind = [&v, &batch]<class T>(std::type_identity<T>) {
        const T tmin0 = interval_start<T>(v.promises);
        constexpr T inf = std::numeric_limits<T>::infinity();
        const auto many = [batch](std::span<const batch_case<T>> cases, std::span<answer<T>> answers) {
            batch(cases, answers);
        };
        const auto one = [batch](const ray_sphere<T>& s, T tmin, T tmax) {
            const batch_case<T> c{s, {tmin, tmax}};
            answer<T> a;
            batch(std::span<const batch_case<T>>(&c, 1), std::span<answer<T>>(&a, 1));
            return a;
        };
        const auto roots_in = [one](const ray_sphere<T>& s, T tmin, T tmax) { return one(s, tmin, tmax).roots; };
        const auto roots = [one, tmin0](const ray_sphere<T>& s) { return one(s, tmin0, inf).roots; };
        const bool interval = takes_interval(v.promises);
        if constexpr (std::is_same_v<T, float>) {
            v.batch_float = many;
            v.answer_float = one;
            v.run_float = roots;
            if (interval) v.run_float_in = roots_in;
        } else {
            v.batch_double = many;
            v.answer_double = one;
            v.run_double = roots;
            if (interval) v.run_double_in = roots_in;
        }
    };
    if (has_float) bind(std::type_identity<float>{});
    if (has_double) bind(std::type_identity<double>{});
}

template <class T, class Fn>
void batch_in_process(const in_process_plugin& plugin, Fn intersect, const contract& promises,
                      std::span<const batch_case<T>> cases, std::span<answer<T>> out) {
    const auto given = plugin_cases<typename batch_function_case<Fn>::type>(cases);
    guarded_answers<rayverify_answer_t<T>> answers(cases.size());
    constexpr const char* function = std::is_same_v<T, float> ? "float batch" : "double batch";
    {
        const in_call marked(plugin, function);
        intersect(given.data(), answers.data(), given.size());
    }
    if (!answers.intact())
        throw plugin_failure(plugin.path,
                             fmt::format("plugin '{}' wrote outside its answers[{}] buffer {}, in its {} function",
                                         plugin.name, cases.size(), failing_case_text(), function),
                             failing_case(cases.front().input, cases.front().interval.tmin,
                                          cases.front().interval.tmax, true));
    take_answers<T>(answers.answers(), promises, cases, out);
}

// A version 1 call's arguments, laid out before a timed pass.
template <class T>
struct call_arguments {
    T o[3], d[3], c[3];
    T r;
};

// The error of a timed pass whose guard areas were overwritten: the pass's
// first case stands for the case, which the pass does not track.
template <class T>
plugin_failure overran_in_timed_pass(const in_process_plugin& plugin, std::string_view buffer, std::size_t cases,
                                     std::string_view function, const ray_sphere<T>& first, T tmin) {
    return plugin_failure(plugin.path,
                          fmt::format("plugin '{}' wrote outside its {} buffer in a timed pass over {} cases, in its "
                                      "{} function (the case shown is the pass's first)",
                                      plugin.name, buffer, cases, function),
                          failing_case(first, tmin, std::numeric_limits<T>::infinity(), false));
}

// A timed pass (timed_pass_fn) through a version 1 plugin's own function: the
// cases laid out as its arguments beforehand, one roots buffer between guard
// areas for the whole pass and the crash marker set once; the guards are
// checked after the pass.
template <class T, class Fn>
timed_pass_fn<T> raw_timed_pass(std::shared_ptr<const in_process_plugin> plugin, Fn intersect, T tmin) {
    return [plugin, intersect, tmin](std::span<const ray_sphere<T>> cases) -> std::function<long long()> {
        if (cases.empty()) return [] { return 0LL; };
        auto arguments = std::make_shared<std::vector<call_arguments<T>>>();
        arguments->reserve(cases.size());
        for (const ray_sphere<T>& s : cases)
            arguments->push_back({{s.origin.x, s.origin.y, s.origin.z},
                                  {s.direction.x, s.direction.y, s.direction.z},
                                  {s.centre.x, s.centre.y, s.centre.z},
                                  s.radius});
        return [plugin, intersect, tmin, arguments, buffer = std::make_shared<guarded_roots<T>>(),
                first = cases.front()] {
            constexpr const char* function = std::is_same_v<T, float> ? "float" : "double";
            constexpr T inf = std::numeric_limits<T>::infinity();
            long long hits = 0;
            {
                const in_call marked(*plugin, function);
                for (const call_arguments<T>& a : *arguments)
                    hits += intersect(a.o, a.d, a.c, a.r, tmin, inf, buffer->roots());
            }
            if (!buffer->intact())
                throw overran_in_timed_pass(*plugin, "roots[2]", arguments->size(), function, first, tmin);
            return hits;
        };
    };
}

// A timed pass through a version 2 plugin's batch function: the cases laid
// out as its batch beforehand, one call for the pass into answers between
// guard areas, checked after it.
template <class T, class Fn>
timed_pass_fn<T> batch_timed_pass(std::shared_ptr<const in_process_plugin> plugin, Fn intersect, T tmin) {
    return [plugin, intersect, tmin](std::span<const ray_sphere<T>> cases) -> std::function<long long()> {
        if (cases.empty()) return [] { return 0LL; };
        std::vector<batch_case<T>> asked;
        asked.reserve(cases.size());
        for (const ray_sphere<T>& s : cases) asked.push_back({s, {tmin, std::numeric_limits<T>::infinity()}});
        auto given = std::make_shared<const std::vector<rayverify_case_t<T>>>(plugin_cases<rayverify_case_t<T>>(std::span<const batch_case<T>>(asked)));
        auto answers = std::make_shared<guarded_answers<rayverify_answer_t<T>>>(cases.size());
        return [plugin, intersect, tmin, given, answers, first = cases.front()] {
            constexpr const char* function = std::is_same_v<T, float> ? "float batch" : "double batch";
            {
                const in_call marked(*plugin, function);
                intersect(given->data(), answers->data(), given->size());
            }
            if (!answers->intact())
                throw overran_in_timed_pass(*plugin, fmt::format("answers[{}]", given->size()), given->size(),
                                            function, first, tmin);
            long long hits = 0;
            for (const rayverify_answer_t<T>& a : answers->answers()) hits += a.count;
            return hits;
        };
    };
}

// ---- The floating-point environment a target's calls run in ----

// One target's environment, and whether a call has changed it yet.
struct environment_guard {
    fp_state given;
    std::string target;
    mutable std::atomic<bool> warned{false};

    void before_call() const {
        if (!(current_fp_state() == given)) set_fp_state(given);
    }
    void after_call() const noexcept {
        const fp_state left = current_fp_state();
        if (!(left == given) && !warned.exchange(true)) {
            try {
                fmt::print(stderr,
                           "rayverify: warning: target '{}' changed the floating-point environment in a call, to {} "
                           "(it was given {}): each call is given its own again, and rayverify's arithmetic runs in "
                           "the IEEE default\n",
                           target, describe_fp_state(left), describe_fp_state(given));
            } catch (...) {
                // the warning is lost; the environment is still restored
            }
        }
        if (!is_ieee_default(left)) set_fp_state(ieee_default_fp_state());
    }
};

template <class R, class... Args>
std::function<R(Args...)> guarded(const std::shared_ptr<const environment_guard>& guard, std::function<R(Args...)> f) {
    if (!f) return f;
    return [guard, f = std::move(f)](Args... args) -> R {
        guard->before_call();
        struct restore_after {
            const environment_guard& guard;
            ~restore_after() { guard.after_call(); }
        } restore{*guard};
        return f(std::forward<Args>(args)...);
    };
}

// A timed pass run in the target's environment: the pass itself is guarded
// as a call is, so the environment is set and checked once per pass.
template <class T>
timed_pass_fn<T> guarded_pass(const std::shared_ptr<const environment_guard>& guard, timed_pass_fn<T> prepare) {
    if (!prepare) return prepare;
    return [guard, prepare = std::move(prepare)](std::span<const ray_sphere<T>> cases) {
        return guarded(guard, prepare(cases));
    };
}

variant load_in_process(const std::filesystem::path& library, const fp_environment_choice& environment) {
    auto plugin = std::make_shared<in_process_plugin>();
    plugin->path = library.string();
    install_hooks();  // before dlopen: a constructor may crash or exit, a truncated library raise SIGBUS
    try {
        library_loading.store(&plugin->path);
        std::atomic_signal_fence(std::memory_order_seq_cst);
        plugin->library = open_library(library);
        library_loading.store(nullptr);
    } catch (const unusable_library& e) {
        library_loading.store(nullptr);
        if (e.only_here) throw plugin_cannot_run_here(library, e.what());
        throw input_error(library.string(), 0, "--plugin", e.what());
    }
    plugin->name = plugin->library.description.name;
    const fp_state run_environment = plugin_run_environment(plugin->library.description, environment);
    std::string environment_text = plugin_environment_text(plugin->library.description, environment);

    variant v = described_variant(plugin->library.description);
    const bool has_float = plugin->library.run_float != nullptr;
    const std::shared_ptr<const in_process_plugin> p = std::move(plugin);
    if (p->library.description.abi == RAYVERIFY_PLUGIN_ABI_VERSION_2) {
        const plugin_description& d = p->library.description;
        bind_batch_entry_points(v, d.has_float, d.has_double,
                                [p, promises = v.promises]<class T>(std::span<const batch_case<T>> cases,
                                                                    std::span<answer<T>> answers) {
                                    const opened_library& l = p->library;
                                    const auto [ray_batch, segment_batch] = [&l] {
                                        if constexpr (std::is_same_v<T, float>)
                                            return std::pair(l.batch_float, l.segments_float);
                                        else
                                            return std::pair(l.batch_double, l.segments_double);
                                    }();
                                    const auto calling = [&](auto entry) {
                                        return [&, entry](std::span<const batch_case<T>> part,
                                                          std::span<answer<T>> out) {
                                            batch_in_process<T>(*p, entry, promises, part, out);
                                        };
                                    };
                                    answer_by_form<T>(cases, answers, calling(ray_batch), calling(segment_batch));
                                });
        v.takes_segment_ends = d.has_segment_entry;
        // bench times a plugin on ray families: a segment-only plugin has none to run on.
        if (!d.has_ray_batch) return in_fp_environment(std::move(v), run_environment, std::move(environment_text));
        if (d.has_float)
            v.timed_pass_float = batch_timed_pass<float>(p, p->library.batch_float, interval_start<float>(v.promises));
        if (d.has_double)
            v.timed_pass_double =
                batch_timed_pass<double>(p, p->library.batch_double, interval_start<double>(v.promises));
        return in_fp_environment(std::move(v), run_environment, std::move(environment_text));
    }
    bind_entry_points(v, has_float, [p](const auto& s, auto tmin, auto tmax, bool interval_asked) {
        if constexpr (std::is_same_v<decltype(tmin), float>)
            return call_in_process(*p, p->library.run_float, s, tmin, tmax, interval_asked);
        else
            return call_in_process(*p, p->library.run_double, s, tmin, tmax, interval_asked);
    });
    v.timed_pass_double = raw_timed_pass<double>(p, p->library.run_double, interval_start<double>(v.promises));
    if (has_float) v.timed_pass_float = raw_timed_pass<float>(p, p->library.run_float, interval_start<float>(v.promises));
    return in_fp_environment(std::move(v), run_environment, std::move(environment_text));
}

// ---- Isolated: the same functions, answered by the plugin's child process ----

variant load_isolated(const std::filesystem::path& library, double timeout_seconds,
                      const fp_environment_choice& environment) {
    const auto host = std::make_shared<plugin_host>(library, timeout_seconds, environment);
    variant v = described_variant(host->description());
    v.thread_safe = false;  // one child process answers one call at a time
    // Its calls run in the child, in the environment the child sets for them; ours stays ours.
    v.fp_environment = plugin_environment_text(host->description(), environment);
    if (host->description().abi == RAYVERIFY_PLUGIN_ABI_VERSION_2) {
        bind_batch_entry_points(v, host->description().has_float, host->description().has_double,
                                [host, promises = v.promises]<class T>(std::span<const batch_case<T>> cases,
                                                                       std::span<answer<T>> answers) {
                                    host->call_batch(cases, answers, promises);
                                });
        v.takes_segment_ends = host->description().has_segment_entry;
        return v;
    }
    bind_entry_points(v, host->description().has_float,
                      [host](const auto& s, auto tmin, auto tmax, bool interval_asked) {
                          return host->call(s, tmin, tmax, interval_asked);
                      });
    return v;
}

}  // namespace

std::optional<std::string> version1_query_name(const contract& c) {
    static const std::pair<int, const char*> kinds[] = {
        {RAYVERIFY_LINE_ROOTS, "RAYVERIFY_LINE_ROOTS"},
        {RAYVERIFY_NEAREST_ON_RAY, "RAYVERIFY_NEAREST_ON_RAY"},
        {RAYVERIFY_ANY_HIT_IN_INTERVAL, "RAYVERIFY_ANY_HIT_IN_INTERVAL"},
        {RAYVERIFY_NEAREST_IN_INTERVAL, "RAYVERIFY_NEAREST_IN_INTERVAL"}};
    const std::string wanted = format_contract(c);
    for (const auto& [query, name] : kinds)
        for (const bool clamps : {false, true}) {
            plugin_internal::plugin_description d;
            d.query = query;
            d.assumes_unit_direction = c.assumes_unit_direction;
            d.reports_tangent = c.reports_tangent;
            d.clamps_to_zero = clamps;
            d.tangent_rule = std::string(c.tangent_rule);
            if (format_contract(plugin_internal::described_variant(d).promises) == wanted)
                return clamps ? std::string(name) + " with clamps_to_zero" : std::string(name);
        }
    return std::nullopt;
}

variant load_plugin(const std::filesystem::path& library, const plugin_isolation& isolation) {
    return isolation.child_process ? load_isolated(library, isolation.timeout_seconds, isolation.environment)
                                   : load_in_process(library, isolation.environment);
}

variant in_fp_environment(variant v, const fp_state& environment, std::string how) {
    const auto guard = std::make_shared<environment_guard>();
    guard->given = environment;
    guard->target = v.name;
    v.run_float = guarded(guard, std::move(v.run_float));
    v.run_double = guarded(guard, std::move(v.run_double));
    v.run_float_in = guarded(guard, std::move(v.run_float_in));
    v.run_double_in = guarded(guard, std::move(v.run_double_in));
    v.answer_float = guarded(guard, std::move(v.answer_float));
    v.answer_double = guarded(guard, std::move(v.answer_double));
    v.batch_float = guarded(guard, std::move(v.batch_float));
    v.batch_double = guarded(guard, std::move(v.batch_double));
    v.timed_pass_float = guarded_pass(guard, std::move(v.timed_pass_float));
    v.timed_pass_double = guarded_pass(guard, std::move(v.timed_pass_double));
    v.fp_environment = std::move(how);
    return v;
}

}  // namespace rayverify

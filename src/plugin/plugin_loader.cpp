#include "plugin/plugin_loader.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <string_view>
#include <type_traits>

#include "core/case_in_progress.h"
#include "plugin/plugin_host.h"
#include "plugin/plugin_library.h"

namespace rayverify {
namespace {

using namespace plugin_internal;

// ---- In process: a crash names the plugin and the case before rayverify dies ----

constexpr int crash_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
struct sigaction previous_actions[std::size(crash_signals)];

// The name of the plugin being called on this thread, nullptr between calls.
thread_local std::atomic<const std::string*> plugin_in_call{nullptr};

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

// Only async-signal-safe calls: write(2) of text that exists already (the
// plugin's name, the announced case's id and source), sigaction, raise.
void crash_handler(int signal, siginfo_t*, void*) {
    const int saved_errno = errno;
    if (const std::string* name = plugin_in_call.load(std::memory_order_relaxed)) {
        write_text("rayverify: plugin ");
        write_text(*name);
        write_text(" crashed (");
        write_text(signal_name(signal));
        if (const corpus_case* c = case_in_progress::current()) {
            write_text(") on case ");
            write_text(c->id);
            write_text(" (");
            write_text(c->source);
            write_text(")");
        } else {
            write_text(") outside any audited case");
        }
        write_text("; rerun with --isolate\n");
    }
    // Back to what was there before (the default, or a sanitizer's handler),
    // which takes the signal as soon as this handler returns.
    for (std::size_t i = 0; i < std::size(crash_signals); ++i)
        if (crash_signals[i] == signal) ::sigaction(signal, &previous_actions[i], nullptr);
    ::raise(signal);
    errno = saved_errno;
}

void install_crash_handler() {
    static std::once_flag once;
    std::call_once(once, [] {
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
    });
}

struct in_process_plugin {
    opened_library library;
    std::string name;  // read by crash_handler
};

// Marks the call for crash_handler.
class in_call {
public:
    explicit in_call(const std::string& name) : previous_(plugin_in_call.load(std::memory_order_relaxed)) {
        plugin_in_call.store(&name, std::memory_order_relaxed);
        std::atomic_signal_fence(std::memory_order_seq_cst);
    }
    ~in_call() {
        std::atomic_signal_fence(std::memory_order_seq_cst);
        plugin_in_call.store(previous_, std::memory_order_relaxed);
    }
    in_call(const in_call&) = delete;
    in_call& operator=(const in_call&) = delete;

private:
    const std::string* previous_;
};

template <class T, class Fn>
root_pair<T> call_in_process(const in_process_plugin& plugin, Fn intersect, const ray_sphere<T>& s, T tmin, T tmax) {
    const T o[3] = {s.origin.x, s.origin.y, s.origin.z};
    const T d[3] = {s.direction.x, s.direction.y, s.direction.z};
    const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
    // NaN until written, so a plugin that reports a hit without writing its roots is judged non_finite.
    T roots[2] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::quiet_NaN()};
    const in_call marked(plugin.name);
    const int count = intersect(o, d, c, s.radius, tmin, tmax, roots);
    return root_pair<T>{count, roots[0], roots[1]};
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

variant load_in_process(const std::filesystem::path& library) {
    auto plugin = std::make_shared<in_process_plugin>();
    try {
        plugin->library = open_library(library);
    } catch (const unusable_library& e) {
        throw input_error(library.string(), 0, "--plugin", e.what());
    }
    plugin->name = plugin->library.description.name;
    install_crash_handler();

    variant v = described_variant(plugin->library.description);
    const bool has_float = plugin->library.run_float != nullptr;
    const std::shared_ptr<const in_process_plugin> p = std::move(plugin);
    bind_entry_points(v, has_float, [p](const auto& s, auto tmin, auto tmax, bool /*interval_asked*/) {
        if constexpr (std::is_same_v<decltype(tmin), float>)
            return call_in_process(*p, p->library.run_float, s, tmin, tmax);
        else
            return call_in_process(*p, p->library.run_double, s, tmin, tmax);
    });
    return v;
}

// ---- Isolated: the same functions, answered by the plugin's child process ----

variant load_isolated(const std::filesystem::path& library, double timeout_seconds) {
    const auto host = std::make_shared<plugin_host>(library, timeout_seconds);
    variant v = described_variant(host->description());
    bind_entry_points(v, host->description().has_float,
                      [host](const auto& s, auto tmin, auto tmax, bool interval_asked) {
                          return host->call(s, tmin, tmax, interval_asked);
                      });
    return v;
}

}  // namespace

variant load_plugin(const std::filesystem::path& library, const plugin_isolation& isolation) {
    return isolation.child_process ? load_isolated(library, isolation.timeout_seconds) : load_in_process(library);
}

}  // namespace rayverify

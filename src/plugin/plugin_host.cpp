#include "plugin/plugin_host.h"

#include <fmt/format.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <thread>
#include <type_traits>
#include <vector>

#include "core/case_in_progress.h"
#include "core/child_processes.h"
#include "core/process_status.h"

namespace rayverify::plugin_internal {
namespace {

using steady = std::chrono::steady_clock;

// The wire. Description: a 32-bit length, then 1 and the fields (texts as a
// 32-bit length and bytes; version 2's after version 1's), or 0 and why the
// library cannot be used. Call: a 32-bit kind, then for a version 1 call o, d,
// c, r, tmin, tmax in T (padded to one size for both kinds: request_size
// bytes in all, so the child reads a call at once), answered by the 32-bit
// count, a 32-bit flag (1: the plugin wrote outside its roots), then
// roots[0], roots[1] in T; for a version 2 batch a 32-bit case count n and n
// rayverify_case_T structs, answered by n rayverify_answer_T structs.
constexpr std::int32_t float_call = 0, double_call = 1, float_batch = 2, double_batch = 3, float_segments = 4,
                       double_segments = 5;
constexpr std::uint32_t largest_batch = 1u << 20;
constexpr std::size_t request_size = sizeof(std::int32_t) + 12 * sizeof(double);
constexpr std::uint32_t longest_description = 1u << 20;
constexpr int child_lost_exit = 121;  // the child's own loop failed (not the plugin)
constexpr int overran_exit = 122;     // the plugin wrote outside a batch's answers

bool send_all(int fd, const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::send(fd, p, size, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

// The child's side: blocks until the bytes are there; false at the end of file.
bool receive_all(int fd, void* data, std::size_t size) {
    char* p = static_cast<char*>(data);
    while (size > 0) {
        const ssize_t n = ::recv(fd, p, size, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

enum class received { all, closed, timed_out };

// rayverify's side: the bytes, unless the socket closes or the deadline passes first.
received receive_by(int fd, void* data, std::size_t size, steady::time_point deadline) {
    char* p = static_cast<char*>(data);
    while (size > 0) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - steady::now()).count();
        if (left <= 0) return received::timed_out;
        pollfd ready{fd, POLLIN, 0};
        const int events = ::poll(&ready, 1, static_cast<int>(std::min<long long>(left, INT_MAX)));
        if (events < 0 && errno != EINTR) return received::closed;
        if (events <= 0) continue;
        const ssize_t n = ::recv(fd, p, size, MSG_DONTWAIT);
        if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
        if (n <= 0) return received::closed;
        p += n;
        size -= static_cast<std::size_t>(n);
    }
    return received::all;
}

void put_u32(std::string& out, std::uint32_t x) { out.append(reinterpret_cast<const char*>(&x), sizeof x); }
void put_text(std::string& out, const std::string& text) {
    put_u32(out, static_cast<std::uint32_t>(text.size()));
    out += text;
}

class reader {
public:
    explicit reader(const std::string& bytes) : bytes_(bytes) {}
    bool u32(std::uint32_t& x) {
        if (bytes_.size() - at_ < sizeof x) return false;
        std::memcpy(&x, bytes_.data() + at_, sizeof x);
        at_ += sizeof x;
        return true;
    }
    bool text(std::string& s) {
        std::uint32_t n = 0;
        if (!u32(n) || bytes_.size() - at_ < n) return false;
        s.assign(bytes_, at_, n);
        at_ += n;
        return true;
    }

private:
    const std::string& bytes_;
    std::size_t at_ = 0;
};

// The version 2 fields, after the version 1 ones.
void encode_version_2(std::string& out, const plugin_description& d) {
    put_u32(out, static_cast<std::uint32_t>(d.abi));
    put_text(out, d.contract_spec);
    put_text(out, d.build);
    put_text(out, d.library_version);
    put_text(out, d.library_configuration);
    put_text(out, std::string(reinterpret_cast<const char*>(&d.environment_at_load), sizeof d.environment_at_load));
    put_u32(out, std::uint32_t{d.has_double});
    put_u32(out, std::uint32_t{d.has_ray_batch});
    put_u32(out, std::uint32_t{d.has_segment_entry});
}

bool decode_version_2(reader& in, plugin_description& d) {
    std::uint32_t abi = 0, has_double = 0, has_ray_batch = 0, has_segment_entry = 0;
    std::string environment;  // the child's fp_state, byte for byte (the same executable)
    if (!in.u32(abi) || !in.text(d.contract_spec) || !in.text(d.build) || !in.text(d.library_version) ||
        !in.text(d.library_configuration) || !in.text(environment) || environment.size() != sizeof(fp_state) ||
        !in.u32(has_double) || !in.u32(has_ray_batch) || !in.u32(has_segment_entry))
        return false;
    d.has_ray_batch = has_ray_batch != 0;
    d.has_segment_entry = has_segment_entry != 0;
    std::memcpy(&d.environment_at_load, environment.data(), sizeof(fp_state));
    d.abi = static_cast<int>(abi);
    d.has_double = has_double != 0;
    return true;
}

std::string encoded(const plugin_description& d) {
    std::string out;
    put_u32(out, 1);
    for (const std::string* text : {&d.name, &d.citation, &d.formula, &d.tangent_rule}) put_text(out, *text);
    for (std::uint32_t x : {static_cast<std::uint32_t>(d.query), std::uint32_t{d.assumes_unit_direction},
                            std::uint32_t{d.reports_tangent}, std::uint32_t{d.clamps_to_zero}, std::uint32_t{d.has_float}})
        put_u32(out, x);
    encode_version_2(out, d);
    return out;
}

bool decoded(const std::string& bytes, plugin_description& d, std::string& problem) {
    reader in(bytes);
    std::uint32_t usable = 0;
    if (!in.u32(usable)) return false;
    if (usable == 0) return in.text(problem);
    std::uint32_t flags[5] = {};
    for (std::string* text : {&d.name, &d.citation, &d.formula, &d.tangent_rule})
        if (!in.text(*text)) return false;
    for (std::uint32_t& x : flags)
        if (!in.u32(x)) return false;
    d.query = static_cast<int>(flags[0]);
    d.assumes_unit_direction = flags[1] != 0;
    d.reports_tangent = flags[2] != 0;
    d.clamps_to_zero = flags[3] != 0;
    d.has_float = flags[4] != 0;
    return decode_version_2(in, d);
}

bool send_message(int fd, const std::string& message) {
    const auto size = static_cast<std::uint32_t>(message.size());
    return send_all(fd, &size, sizeof size) && send_all(fd, message.data(), message.size());
}

// The child's side of a version 2 batch: n cases in, n answers out.
template <class Case, class Answer, class Fn>
bool answer_batch(int fd, Fn intersect) {
    std::uint32_t n = 0;
    if (!intersect || !receive_all(fd, &n, sizeof n) || n > largest_batch) return false;
    std::vector<Case> cases(n);
    if (!receive_all(fd, cases.data(), n * sizeof(Case))) return false;
    guarded_answers<Answer> answers(n);
    intersect(cases.data(), answers.data(), n);
    if (!answers.intact()) ::_exit(overran_exit);
    return send_all(fd, answers.data(), n * sizeof(Answer));
}

template <class T, class Fn>
bool answer_call(int fd, Fn intersect, const unsigned char* request) {
    T in[12];
    std::memcpy(in, request + sizeof(std::int32_t), sizeof in);
    guarded_roots<T> buffer;
    const std::int32_t count = intersect(in, in + 3, in + 6, in[9], in[10], in[11], buffer.roots());
    const std::int32_t overrun = buffer.intact() ? 0 : 1;
    unsigned char reply[2 * sizeof count + 2 * sizeof(T)];
    std::memcpy(reply, &count, sizeof count);
    std::memcpy(reply + sizeof count, &overrun, sizeof overrun);
    std::memcpy(reply + 2 * sizeof count, buffer.roots(), 2 * sizeof(T));
    return send_all(fd, reply, sizeof reply);
}

// The child: a copy of rayverify at the moment of the fork. It must never
// return or unwind into the parent's frames, so it ends in _exit, which also
// keeps the parent's atexit handlers and buffered output from running twice.
[[noreturn]] void run_child(const std::filesystem::path& library, int fd, pid_t parent,
                            const fp_environment_choice& environment) noexcept {
    try {
        // Killed with rayverify, even in the middle of a call that never returns.
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(child_lost_exit);
        // A crash kills the child by its signal, which the parent reports;
        // no handler of rayverify's (or a sanitizer's) may turn it into something else.
        for (int signal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(signal, SIG_DFL);
        // Only our end of the socket stays open: the child holds none of the
        // parent's other descriptors (other plugins' sockets, output files).
        if (fd > 3) ::close_range(3, static_cast<unsigned>(fd) - 1, 0);
        ::close_range(static_cast<unsigned>(fd) + 1, ~0u, 0);

        opened_library opened;
        std::string message;
        try {
            opened = open_library(library);
            message = encoded(opened.description);
        } catch (const unusable_library& e) {
            message.clear();
            put_u32(message, 0);
            put_text(message, e.what());
        }
        if (!send_message(fd, message) || !opened.handle) ::_exit(0);
        const fp_state plugin_environment = plugin_run_environment(opened.description, environment);
        for (;;) {
            unsigned char request[request_size];
            std::int32_t kind = 0;
            if (!receive_all(fd, &kind, sizeof kind)) ::_exit(0);  // rayverify closed its end: done
            set_fp_state(plugin_environment);  // as it was given, whatever its last call left
            bool answered = false;
            if (kind == float_batch) {
                answered = answer_batch<rayverify_case_float, rayverify_answer_float>(fd, opened.batch_float);
            } else if (kind == double_batch) {
                answered = answer_batch<rayverify_case_double, rayverify_answer_double>(fd, opened.batch_double);
            } else if (kind == float_segments) {
                answered = answer_batch<rayverify_segment_float, rayverify_answer_float>(fd, opened.segments_float);
            } else if (kind == double_segments) {
                answered = answer_batch<rayverify_segment_double, rayverify_answer_double>(fd, opened.segments_double);
            } else {
                std::memcpy(request, &kind, sizeof kind);
                if (!receive_all(fd, request + sizeof kind, request_size - sizeof kind)) ::_exit(0);
                answered = kind == double_call ? answer_call<double>(fd, opened.run_double, request)
                           : kind == float_call && opened.run_float ? answer_call<float>(fd, opened.run_float, request)
                                                                    : false;
            }
            if (!answered) break;
        }
    } catch (...) {
    }
    ::_exit(child_lost_exit);
}

std::string how_it_ended(int status) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == child_lost_exit) return "lost its connection to rayverify";
    if (WIFEXITED(status) && WEXITSTATUS(status) == overran_exit) return "wrote outside its answers buffer";
    return describe_wait_status(status);
}

}  // namespace

plugin_host::plugin_host(std::filesystem::path library, double timeout_seconds,
                         const fp_environment_choice& environment)
    : library_(std::move(library)), timeout_seconds_(timeout_seconds) {
    const auto fail = [&](const std::string& problem) { throw input_error(library_.string(), 0, "--plugin", problem); };
    int ends[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0)
        fail(fmt::format("--isolate: cannot create a socket pair: {}", std::strerror(errno)));
    // Output buffered now would otherwise be written a second time by a child that calls exit().
    std::fflush(nullptr);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int error = errno;
        ::close(ends[0]);
        ::close(ends[1]);
        fail(fmt::format("--isolate: cannot start a process for the plugin: {}", std::strerror(error)));
    }
    if (pid == 0) {
        ::close(ends[0]);
        run_child(library_, ends[1], parent, environment);
    }
    ::close(ends[1]);
    started_child(pid);
    fd_ = ends[0];
    pid_ = pid;

    const steady::time_point deadline = deadline_after(timeout_seconds_);
    std::uint32_t size = 0;
    std::string bytes;
    received got = receive_by(fd_, &size, sizeof size, deadline);
    if (got == received::all) {
        if (size > longest_description) got = received::closed;
        else {
            bytes.resize(size);
            got = receive_by(fd_, bytes.data(), size, deadline);
        }
    }
    std::string problem;
    if (got == received::all && !decoded(bytes, description_, problem)) problem = "sent a garbled description";
    if (got == received::all && problem.empty()) return;
    if (got == received::all) {
        ended();  // the child exits once it has said why
        fail(problem);
    }
    const std::string happened = got == received::timed_out ? timed_out() : ended();
    fail(fmt::format("its process {} while loading it (dlopen, or rayverify_plugin_describe())", happened));
}

plugin_host::~plugin_host() { ended(); }

std::string plugin_host::ended() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (pid_ <= 0) return "ended";
    // The socket closes as the child exits: it is reaped at once, or killed
    // when it lingers (a plugin that closed the socket itself).
    const std::optional<int> status = reap_child(pid_, pid_, timeout_seconds_);
    child_ended(pid_);
    pid_ = -1;
    return status ? how_it_ended(*status) : "ended";
}

std::string plugin_host::timed_out() {
    if (pid_ > 0) ::kill(pid_, SIGKILL);
    ended();
    return fmt::format("gave no answer within {:g} s (its process was killed)", timeout_seconds_);
}

template <class T>
root_pair<T> plugin_host::call_in(const ray_sphere<T>& s, T tmin, T tmax, bool interval_asked) {
    constexpr std::int32_t kind = std::is_same_v<T, float> ? float_call : double_call;
    const T in[12] = {s.origin.x, s.origin.y, s.origin.z, s.direction.x, s.direction.y, s.direction.z,
                      s.centre.x, s.centre.y, s.centre.z, s.radius,      tmin,          tmax};
    unsigned char request[request_size] = {};
    std::memcpy(request, &kind, sizeof kind);
    std::memcpy(request + sizeof kind, in, sizeof in);
    std::string happened = "is no longer running (it failed on an earlier call)";
    if (fd_ >= 0) {
        const steady::time_point deadline = deadline_after(timeout_seconds_);
        std::int32_t count = 0, overrun = 0;
        T roots[2];
        unsigned char reply[2 * sizeof count + sizeof roots];
        const received got =
            send_all(fd_, request, request_size) ? receive_by(fd_, reply, sizeof reply, deadline) : received::closed;
        if (got == received::all) {
            std::memcpy(&count, reply, sizeof count);
            std::memcpy(&overrun, reply + sizeof count, sizeof overrun);
            std::memcpy(roots, reply + 2 * sizeof count, sizeof roots);
            if (overrun == 0) return {count, roots[0], roots[1]};
            happened = "wrote outside its roots[2] buffer";
        } else {
            happened = got == received::timed_out ? timed_out() : ended();
        }
    }
    throw plugin_failure(library_,
                         fmt::format("plugin '{}' {} {}, in its {} function", description_.name, happened,
                                     failing_case_text(), std::is_same_v<T, float> ? "float" : "double"),
                         failing_case(s, tmin, tmax, interval_asked));
}

template <class T>
void plugin_host::batch_in(std::span<const batch_case<T>> cases, std::span<answer<T>> out, const contract& promises) {
    answer_by_form<T>(
        cases, out,
        [&](std::span<const batch_case<T>> part, std::span<answer<T>> answers) { batch_of<T, false>(part, answers, promises); },
        [&](std::span<const batch_case<T>> part, std::span<answer<T>> answers) { batch_of<T, true>(part, answers, promises); });
}

template <class T, bool segments>
void plugin_host::batch_of(std::span<const batch_case<T>> cases, std::span<answer<T>> out, const contract& promises) {
    using case_t = plugin_case_t<T, segments>;
    using answer_t = std::conditional_t<std::is_same_v<T, float>, rayverify_answer_float, rayverify_answer_double>;
    constexpr std::int32_t kind = segments ? (std::is_same_v<T, float> ? float_segments : double_segments)
                                           : (std::is_same_v<T, float> ? float_batch : double_batch);
    if (cases.empty()) return;
    std::string happened = "is no longer running (it failed on an earlier call)";
    if (fd_ >= 0 && cases.size() <= largest_batch) {
        std::string request;
        request.append(reinterpret_cast<const char*>(&kind), sizeof kind);
        const auto n = static_cast<std::uint32_t>(cases.size());
        request.append(reinterpret_cast<const char*>(&n), sizeof n);
        for (const batch_case<T>& c : cases) {
            const case_t given = plugin_case<case_t>(c);
            request.append(reinterpret_cast<const char*>(&given), sizeof given);
        }
        std::vector<answer_t> answers(cases.size());
        const steady::time_point deadline = deadline_after(timeout_seconds_);
        const received got = send_all(fd_, request.data(), request.size())
                                 ? receive_by(fd_, answers.data(), answers.size() * sizeof(answer_t), deadline)
                                 : received::closed;
        if (got == received::all) {
            for (std::size_t i = 0; i < cases.size(); ++i) out[i] = answer_from<T>(answers[i], promises, cases[i].input);
            return;
        }
        happened = got == received::timed_out ? timed_out() : ended();
    }
    const corpus_case* announced = case_in_progress::current();
    corpus_case failing =
        failing_case(cases.front().input, cases.front().interval.tmin, cases.front().interval.tmax, true);
    const std::string where =
        announced ? fmt::format("on a batch of {} case{} from case {} ({})", cases.size(), cases.size() == 1 ? "" : "s",
                                announced->id, announced->source)
                  : fmt::format("on a batch of {} case{} given outside any audited case (the first below)",
                                cases.size(), cases.size() == 1 ? "" : "s");
    throw plugin_failure(library_,
                         fmt::format("plugin '{}' {} {}, in its {} batch function", description_.name, happened, where,
                                     std::is_same_v<T, float> ? "float" : "double"),
                         std::move(failing));
}

void plugin_host::call_batch(std::span<const batch_case<float>> cases, std::span<answer<float>> out,
                             const contract& promises) {
    batch_in<float>(cases, out, promises);
}

void plugin_host::call_batch(std::span<const batch_case<double>> cases, std::span<answer<double>> out,
                             const contract& promises) {
    batch_in<double>(cases, out, promises);
}

root_pair<float> plugin_host::call(const ray_sphere<float>& s, float tmin, float tmax, bool interval_asked) {
    return call_in<float>(s, tmin, tmax, interval_asked);
}

root_pair<double> plugin_host::call(const ray_sphere<double>& s, double tmin, double tmax, bool interval_asked) {
    return call_in<double>(s, tmin, tmax, interval_asked);
}

}  // namespace rayverify::plugin_internal

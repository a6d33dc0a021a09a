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
#include <thread>
#include <type_traits>

#include "core/case_in_progress.h"
#include "core/process_status.h"

namespace rayverify::plugin_internal {
namespace {

using steady = std::chrono::steady_clock;

// The wire. Description: a 32-bit length, then 1 and the fields (texts as a
// 32-bit length and bytes), or 0 and why the library cannot be used. Call:
// request_size bytes, a 32-bit kind then o, d, c, r, tmin, tmax in T (one
// size for both kinds, so the child reads a call at once). Answer: the 32-bit
// count, a 32-bit flag (1: the plugin wrote outside its roots), then
// roots[0], roots[1] in T.
constexpr std::int32_t float_call = 0, double_call = 1;
constexpr std::size_t request_size = sizeof(std::int32_t) + 12 * sizeof(double);
constexpr std::uint32_t longest_description = 1u << 20;
constexpr int child_lost_exit = 121;  // the child's own loop failed (not the plugin)

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

std::string encoded(const plugin_description& d) {
    std::string out;
    put_u32(out, 1);
    for (const std::string* text : {&d.name, &d.citation, &d.formula, &d.tangent_rule}) put_text(out, *text);
    for (std::uint32_t x : {static_cast<std::uint32_t>(d.query), std::uint32_t{d.assumes_unit_direction},
                            std::uint32_t{d.reports_tangent}, std::uint32_t{d.clamps_to_zero}, std::uint32_t{d.has_float}})
        put_u32(out, x);
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
    return true;
}

bool send_message(int fd, const std::string& message) {
    const auto size = static_cast<std::uint32_t>(message.size());
    return send_all(fd, &size, sizeof size) && send_all(fd, message.data(), message.size());
}

template <class T, class Fn>
bool answer(int fd, Fn intersect, const unsigned char* request) {
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
[[noreturn]] void run_child(const std::filesystem::path& library, int fd, pid_t parent) noexcept {
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
        for (;;) {
            unsigned char request[request_size];
            if (!receive_all(fd, request, request_size)) ::_exit(0);  // rayverify closed its end: done
            std::int32_t kind = 0;
            std::memcpy(&kind, request, sizeof kind);
            const bool answered = kind == double_call ? answer<double>(fd, opened.run_double, request)
                                  : kind == float_call && opened.run_float
                                      ? answer<float>(fd, opened.run_float, request)
                                      : false;
            if (!answered) break;
        }
    } catch (...) {
    }
    ::_exit(child_lost_exit);
}

std::string how_it_ended(int status) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == child_lost_exit) return "lost its connection to rayverify";
    return describe_wait_status(status);
}

}  // namespace

plugin_host::plugin_host(std::filesystem::path library, double timeout_seconds)
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
        run_child(library_, ends[1], parent);
    }
    ::close(ends[1]);
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

root_pair<float> plugin_host::call(const ray_sphere<float>& s, float tmin, float tmax, bool interval_asked) {
    return call_in<float>(s, tmin, tmax, interval_asked);
}

root_pair<double> plugin_host::call(const ray_sphere<double>& s, double tmin, double tmax, bool interval_asked) {
    return call_in<double>(s, tmin, tmax, interval_asked);
}

}  // namespace rayverify::plugin_internal
